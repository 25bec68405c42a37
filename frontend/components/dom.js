// DOM helpers and formatting shared by the views.

/**
 * Create an element: h("button", {class: "btn", onclick: fn}, "Text", child...).
 * Attributes starting with "on" become listeners; `dataset`/`style` objects are merged;
 * boolean true sets an empty attribute, false/null/undefined leaves it out.
 */
export function h(tag, attrs = {}, ...children) {
  const el = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (v === false || v === null || v === undefined) continue;
    if (k.startsWith("on") && typeof v === "function") el.addEventListener(k.slice(2), v);
    else if (k === "dataset") Object.assign(el.dataset, v);
    else if (k === "style" && typeof v === "object") Object.assign(el.style, v);
    else if (k === "class") el.className = v;
    else if (k === "html") el.innerHTML = v; // only for trusted, static markup
    else if (k in el && typeof v !== "string" && k !== "list") el[k] = v;
    else el.setAttribute(k, v === true ? "" : String(v));
  }
  append(el, children);
  return el;
}

function append(el, children) {
  for (const c of children.flat(Infinity)) {
    if (c === null || c === undefined || c === false) continue;
    el.append(c instanceof Node ? c : document.createTextNode(String(c)));
  }
}

/** Replace the children of `el`. */
export function setChildren(el, ...children) {
  el.replaceChildren();
  append(el, children);
  return el;
}

/** Unit as people write it: m/s^2 → m/s², (m/s^2)^2/Hz → (m/s²)²/Hz. */
export function prettyUnit(u) {
  if (!u || u === "-") return u === "-" ? "–" : "";
  return String(u).replace(/\^2/g, "²").replace(/\^3/g, "³").replace(/\^4/g, "⁴")
    .replace(/\^1\.75/g, "^1.75");
}

/** Number with sensible significant digits; "–" for null/NaN. */
export function fmt(v, digits = 3) {
  if (v === null || v === undefined || typeof v !== "number" || !Number.isFinite(v)) return "–";
  const a = Math.abs(v);
  if (a !== 0 && (a >= 1e6 || a < 1e-3)) return v.toExponential(Math.max(0, digits - 1));
  return Number(v.toPrecision(digits)).toLocaleString("en-GB", { maximumFractionDigits: 6 });
}

/** Fixed decimals (Sperling: 2). */
export function fixed(v, d = 2) {
  return typeof v === "number" && Number.isFinite(v) ? v.toFixed(d) : "–";
}

/** A fraction as a signed percentage: +13.6 %, −2.0 % (a value that rounds to zero: 0.0 %). */
export function pct(v, d = 1) {
  if (typeof v !== "number" || !Number.isFinite(v)) return "–";
  const s = (100 * v).toFixed(d);
  if (Number(s) === 0) return `${(0).toFixed(d)} %`;
  return `${v > 0 ? "+" : "−"}${s.replace("-", "")} %`;
}

/** Seconds as "1.2 s", "3 min 4 s", "1 h 2 min". */
export function duration(s) {
  if (typeof s !== "number" || !Number.isFinite(s)) return "–";
  if (s < 60) return `${s < 10 ? s.toFixed(1) : Math.round(s)} s`;
  if (s < 3600) return `${Math.floor(s / 60)} min ${Math.round(s % 60)} s`;
  return `${Math.floor(s / 3600)} h ${Math.round((s % 3600) / 60)} min`;
}

export function when(iso) {
  if (!iso) return "–";
  const d = new Date(iso);
  if (Number.isNaN(d.getTime())) return iso;
  const today = new Date();
  const sameDay = d.toDateString() === today.toDateString();
  return sameDay ? d.toLocaleTimeString("en-GB") : d.toLocaleString("en-GB");
}

export function debounce(fn, ms) {
  let t;
  return (...args) => {
    clearTimeout(t);
    t = setTimeout(() => fn(...args), ms);
  };
}

/** Save text or a Blob as a file. */
export function saveFile(name, content, type = "text/plain") {
  const blob = content instanceof Blob ? content : new Blob([content], { type });
  const url = URL.createObjectURL(blob);
  const a = h("a", { href: url, download: name, hidden: true });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 5000);
}

/** A file name fragment from free text. */
export function slug(s) {
  return String(s || "flexride").replace(/[^A-Za-z0-9._-]+/g, "_").replace(/^_+|_+$/g, "").slice(0, 60) || "flexride";
}

/** Status badge (queued/running/succeeded/failed/cancelled/partial/empty). */
export function badge(status) {
  return h("span", { class: `badge st-${status}` }, status);
}

/** Whole percent of a fraction for people: 100 % only when the work is done – an unfinished
 * (queued or running) one shows at most 99 %, and 99.6 % is not rounded up. */
export function percentDone(fraction, status = "") {
  const p = Math.max(0, Math.min(1, Number(fraction) || 0));
  const active = status === "queued" || status === "running";
  return p >= 1 && !active ? 100 : Math.min(99, Math.floor(100 * p));
}

/** A progress bar with an accessible value (see percentDone). */
export function progressBar(fraction, label = "Progress", status = "") {
  const n = percentDone(fraction, status);
  const pctText = `${n} %`;
  return h("div", {
    class: `progress st-${status}`, role: "progressbar", "aria-label": label,
    "aria-valuemin": "0", "aria-valuemax": "100", "aria-valuenow": String(n),
    "aria-valuetext": pctText,
  }, h("div", { class: "progress-fill", style: { width: `${n}%` } }),
  h("span", { class: "progress-text" }, pctText));
}

/** A message box: kind = info | error | warn | empty. */
export function notice(kind, title, ...body) {
  return h("div", { class: `notice notice-${kind}`, role: kind === "error" ? "alert" : "status" },
    title ? h("strong", {}, title) : null, body.length ? h("div", {}, ...body) : null);
}

/** A loading placeholder. */
export function loading(text = "Loading…") {
  return h("div", { class: "loading", role: "status", "aria-live": "polite" }, h("span", { class: "spinner", "aria-hidden": "true" }), text);
}

/** Error box for an ApiError or any error. */
export function errorBox(err, title = "Something went wrong") {
  const items = (err?.items || []).filter((i) => i && i.msg);
  return notice("error", err?.unreachable ? "Service unreachable" : title,
    h("p", {}, err?.message || String(err)),
    items.length > 1 ? h("ul", {}, items.map((i) => h("li", {}, i.msg))) : null);
}

/** Tabs (WAI-ARIA tablist) – returns {el, select(id)}; panels rendered lazily by render(id, panel). */
export function tabs(items, render, { label = "Views", initial } = {}) {
  const list = h("div", { class: "tablist", role: "tablist", "aria-label": label });
  const panels = h("div", { class: "tabpanels" });
  const made = new Map();
  const buttons = items.map((it, i) => h("button", {
    class: "tab", role: "tab", id: `tab-${it.id}`, type: "button",
    "aria-controls": `panel-${it.id}`, "aria-selected": "false", tabindex: "-1",
    onclick: () => select(it.id, true),
    onkeydown: (e) => {
      const k = e.key;
      let j = null;
      if (k === "ArrowRight") j = (i + 1) % items.length;
      else if (k === "ArrowLeft") j = (i - 1 + items.length) % items.length;
      else if (k === "Home") j = 0;
      else if (k === "End") j = items.length - 1;
      if (j !== null) {
        e.preventDefault();
        select(items[j].id, true);
        buttons[j].focus();
      }
    },
  }, it.label));
  list.append(...buttons);
  function select(id, user = false) {
    items.forEach((it, i) => {
      const on = it.id === id;
      buttons[i].setAttribute("aria-selected", String(on));
      buttons[i].tabIndex = on ? 0 : -1;
      let panel = made.get(it.id);
      if (on && !panel) {
        panel = h("div", { class: "tabpanel", role: "tabpanel", id: `panel-${it.id}`, "aria-labelledby": `tab-${it.id}`, tabindex: "0" });
        made.set(it.id, panel);
        panels.append(panel);
        render(it.id, panel);
      }
      if (panel) panel.hidden = !on;
    });
    if (user && typeof onSelect === "function") onSelect(id);
    window.dispatchEvent(new Event("resize")); // plots in a panel that was hidden
  }
  let onSelect = null;
  const el = h("div", { class: "tabs" }, list, panels);
  select(initial || items[0].id);
  return { el, select, set onSelect(fn) { onSelect = fn; } };
}

/**
 * Sortable, accessible data table. columns: [{key, label, num?, format?(v,row), title?, sep?}];
 * `groups` ([{label, span}], spans summing to the column count) adds a header row above the
 * columns (e.g. "Vertical" over its columns). A table wider than its box shows a scroll cue.
 */
export function dataTable(columns, rows, { caption, onRow, rowLabel, className = "", groups = null, rowClass = null } = {}) {
  let sortKey = null;
  let asc = true;
  const tbody = h("tbody");
  const heads = columns.map((c) => h("th", { scope: "col", class: `${c.num ? "num" : ""}${c.sep ? " sep" : ""}`, "aria-sort": "none", title: c.title || null },
    h("button", { type: "button", class: "sort", onclick: () => sortBy(c.key) }, c.label)));
  function val(row, c) {
    return typeof c.value === "function" ? c.value(row) : row[c.key];
  }
  function fill() {
    const list = rows.slice();
    if (sortKey) {
      const c = columns.find((x) => x.key === sortKey);
      list.sort((a, b) => {
        const x = val(a, c);
        const y = val(b, c);
        if (x === y) return 0;
        if (x === null || x === undefined) return 1;
        if (y === null || y === undefined) return -1;
        return (x < y ? -1 : 1) * (asc ? 1 : -1);
      });
    }
    tbody.replaceChildren(...list.map((r) => {
      const tr = h("tr", {}, columns.map((c, i) => {
        const v = val(r, c);
        const content = c.format ? c.format(v, r) : (typeof v === "number" ? fmt(v) : v ?? "–");
        const cls = `${c.num ? "num" : ""}${c.sep ? " sep" : ""}${c.cellClass ? ` ${c.cellClass(v, r) || ""}` : ""}`.trim();
        return i === 0 ? h("th", { scope: "row", class: cls }, content)
          : h("td", { class: cls }, content);
      }));
      if (rowClass) {
        const rc = rowClass(r);
        if (rc) tr.className = rc;
      }
      if (onRow) {
        tr.classList.add("clickable");
        tr.tabIndex = 0;
        if (rowLabel) tr.setAttribute("aria-label", rowLabel(r));
        tr.addEventListener("click", (e) => { if (!e.target.closest("a,button")) onRow(r); });
        tr.addEventListener("keydown", (e) => { if (e.key === "Enter" && e.target === tr) onRow(r); });
      }
      return tr;
    }));
  }
  function sortBy(key) {
    asc = sortKey === key ? !asc : true;
    sortKey = key;
    heads.forEach((th, i) => th.setAttribute("aria-sort", columns[i].key === key ? (asc ? "ascending" : "descending") : "none"));
    fill();
  }
  fill();
  const groupRow = groups ? h("tr", { class: "group-head" }, groups.map((g, i) => h("th", { scope: "colgroup", colspan: String(g.span), class: i ? "sep" : "" }, g.label || ""))) : null;
  const table = h("table", { class: "data" }, caption ? h("caption", {}, caption) : null, h("thead", {}, groupRow, h("tr", {}, heads)), tbody);
  const wrap = h("div", { class: `table-wrap ${className}` }, table);
  return withScrollCue(wrap);
}

/** A box that may scroll sideways: while its content is wider, a shadow at the edge that
 * still has columns and a line "scroll sideways for more columns" under it. */
export function withScrollCue(wrap) {
  const cue = h("p", { class: "scroll-cue", hidden: true, "aria-hidden": "true" }, "Scroll sideways for more columns →");
  const box = h("div", { class: "scroll-box" }, wrap, cue);
  const check = () => {
    const over = wrap.scrollWidth > wrap.clientWidth + 1;
    wrap.classList.toggle("scroll-x", over);
    cue.hidden = !over;
  };
  if (window.ResizeObserver) new ResizeObserver(check).observe(wrap);
  requestAnimationFrame(check);
  return box;
}

/** Rows → CSV text (RFC 4180 quoting). */
export function toCsv(header, rows) {
  const q = (v) => {
    if (v === null || v === undefined) return "";
    const s = typeof v === "number" ? (Number.isFinite(v) ? String(v) : "") : String(v);
    return /[",\n]/.test(s) ? `"${s.replace(/"/g, '""')}"` : s;
  };
  return [header, ...rows].map((r) => r.map(q).join(",")).join("\n") + "\n";
}

/** Parts of a channel name <body>.<point>.<quantity>.<direction> (the naming rule of
 * flexride.results.Channel; GET /jobs/{id}/channels gives the same parts), or null. The
 * dashboard's only parser of channel names. */
export function parseChannel(name) {
  const p = String(name).split(".");
  if (p.length !== 4 || p.some((x) => !x)) return null;
  const [body, point, quantity, direction] = p;
  return { body, point, quantity, direction };
}

/** A channel name from its parts (the inverse of parseChannel). */
export function channelName({ body, point, quantity, direction }) {
  return `${body}.${point}.${quantity}.${direction}`;
}

/** Pretty channel label: carbody.PC.acc.z → "car body PC acc z". */
export function channelLabel(name) {
  const c = parseChannel(name);
  if (!c) return name;
  const bodyName = c.body === "carbody" ? "car body" : c.body.replace(/(\d+)$/, " $1");
  return `${bodyName} ${c.point} ${c.quantity} ${c.direction}`;
}

export const DIRECTION_NAMES = { z: "vertical", y: "lateral", x: "longitudinal", n: "normal" };
