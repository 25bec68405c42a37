// Mesh convergence of a study (issue 33: the paper's element-size pre-calculation, Fig. 4): for
// each table of GET /studies/{id} → tables.mesh_convergence (one per body and group of the
// other axes) the claim's verdict, the chosen quantity against element size with the
// Richardson-extrapolated value and the finest mesh's GCI band, and a table of every quantity.
// The numbers are the service's (flexride.study.mesh_convergence); nothing is estimated here.

import { h, setChildren, fmt, pct, prettyUnit, dataTable } from "./dom.js";
import { plotCard, baseLayout, COLORS } from "./plot.js";

const GROUP_ORDER = { force: 0, frequency: 1, comfort: 2 };
const GROUP_NAMES = { force: "Air-spring forces", frequency: "Elastic frequencies", comfort: "Comfort" };
const BODY_NAMES = { carbody: "Car body", frames: "Bogie frames" };
const OSCILLATORY = "Oscillatory convergence: the differences between the meshes change sign, so the spread of the values, not an asymptote, bounds the error";

/** Significant digits of a value: 4 (e.g. 5.150 Hz, 1.980, 100.0 N). */
const num = (v) => fmt(v, 4);
const unitText = (u) => (u === "-" ? "–" : prettyUnit(u));

/** "smooth-straight · 80 km/h · flexible body": the condition first, the body model last. */
export function meshGroupLabel(group) {
  const g = group || {};
  const rank = (k) => (k === "condition" ? 0 : k === "speed_kmh" ? 1 : k === "body_model" ? 3 : 2);
  const text = (k, v) => {
    if (k === "speed_kmh") return `${fmt(Number(v))} km/h`; // the service gives it as text
    if (k === "body_model") return `${v} body`;
    if (k === "condition") return String(v);
    return `${k.split(".").pop().replace(/_/g, " ")} ${v}`;
  };
  return Object.keys(g).sort((a, b) => rank(a) - rank(b)).map((k) => text(k, g[k])).join(" · ") || "all jobs";
}

/** Every quantity of the tables, [{key, label, unit, group}], force rows first (the service's
 * order within a group). */
export function meshQuantities(tables) {
  const seen = new Map();
  for (const t of tables) {
    for (const r of t.rows || []) if (!seen.has(r.key)) seen.set(r.key, { key: r.key, label: r.label, unit: r.unit, group: r.group });
  }
  return [...seen.values()].map((q, i) => [q, i])
    .sort(([a, i], [b, j]) => (GROUP_ORDER[a.group] ?? 9) - (GROUP_ORDER[b.group] ?? 9) || i - j)
    .map(([q]) => q);
}

/** The figure of one row: the value per mesh (markers), the extrapolated value (dashed) and
 * the finest mesh's GCI band (± gci_fine × |finest value|, shaded), the judged size marked. */
export function meshFigure(table, row) {
  const sizes = table.sizes_m;
  const ref = table.reference_size_m;
  const unit = unitText(row.unit);
  const pts = sizes.map((s, i) => [s, row.values[i], table.realisations?.[i] ?? 1]).filter(([, v]) => v !== null && v !== undefined);
  const xmax = Math.max(...sizes) * 1.06;
  const est = row.estimate;
  const data = [];
  const ext = est?.extrapolated;
  const gci = est?.gci_fine;
  const f1 = est?.values?.[0];
  if (est && Number.isFinite(gci) && Number.isFinite(f1)) {
    const half = gci * Math.abs(f1);
    data.push({
      type: "scatter", mode: "lines", meta: "gci", fill: "toself", fillcolor: "rgba(0,114,178,0.14)",
      line: { width: 0 }, hoverinfo: "skip",
      name: `GCI of the finest mesh (${fmt(est.sizes_m[0])} m): ±${fmt(100 * gci, 3)} %`,
      x: [0, xmax, xmax, 0, 0], y: [f1 - half, f1 - half, f1 + half, f1 + half, f1 - half],
    });
  }
  if (est && Number.isFinite(ext)) {
    data.push({
      type: "scatter", mode: "lines", meta: "extrapolated", line: { color: COLORS[1], dash: "dash", width: 2 },
      name: `extrapolated: ${num(ext)} ${unit}`,
      x: [0, xmax], y: [ext, ext],
      hovertemplate: `extrapolated (h → 0): ${num(ext)} ${unit}<extra></extra>`,
    });
  }
  data.push({
    type: "scatter", mode: "lines+markers", meta: "mesh", name: "per mesh",
    x: pts.map((p) => p[0]), y: pts.map((p) => p[1]),
    customdata: pts.map((p) => p[2]),
    line: { color: COLORS[0], width: 1.5 },
    marker: { color: COLORS[0], size: pts.map((p) => (Math.abs(p[0] - ref) < 1e-9 ? 13 : 9)), symbol: pts.map((p) => (Math.abs(p[0] - ref) < 1e-9 ? "diamond" : "circle")) },
    hovertemplate: `%{x} m: %{y:.4g} ${unit}<br>%{customdata} realisation(s)<extra></extra>`,
  });
  const layout = baseLayout("Element size (m)", `${row.label} (${unit})`, {
    xaxis: { range: [0, xmax], rangemode: "tozero" },
    margin: { l: 72, r: 16, t: 24, b: 52 },
    legend: { orientation: "h", y: -0.24, x: 0, yanchor: "top" },
    shapes: sizes.some((s) => Math.abs(s - ref) < 1e-9) ? [{ type: "line", xref: "x", yref: "paper", x0: ref, x1: ref, y0: 0, y1: 1, line: { color: "#9aa3ad", dash: "dot", width: 1 } }] : [],
    annotations: sizes.some((s) => Math.abs(s - ref) < 1e-9) ? [{ xref: "x", yref: "paper", x: ref, y: 1, yanchor: "bottom", text: `${fmt(ref)} m (judged)`, showarrow: false, font: { size: 11, color: "#52606d" } }] : [],
  });
  return { data, layout };
}

function orderCell(est) {
  if (!est || est.order === null || est.order === undefined) {
    return h("span", { title: est ? "No observed order: the three finest values do not converge monotonically (or are equal)" : "No estimate: fewer than two meshes with a value" }, "–");
  }
  const text = `${est.order.toFixed(2)}${est.order_assumed ? " (assumed)" : ""}`;
  if (est.oscillatory) return h("span", { class: "mesh-osc", title: OSCILLATORY }, `~${text}`);
  return h("span", { title: est.order_assumed ? "Two meshes only: the elements' order is assumed" : "Observed order of convergence of the three finest meshes" }, text);
}

/** The table of every quantity of one mesh-convergence table. */
export function meshTable(table, { caption } = {}) {
  const sizes = table.sizes_m;
  const ref = table.reference_size_m;
  const isRef = (s) => Math.abs(s - ref) < 1e-9;
  const cols = [
    { key: "label", label: "Quantity" },
    { key: "unit", label: "Unit", format: (v) => unitText(v) },
    ...sizes.map((s, i) => ({
      key: `v${i}`, label: `${fmt(s)} m`, num: true, sep: i === 0, value: (r) => r.values[i],
      title: `${isRef(s) ? "The judged size; " : ""}the value on the ${fmt(s)} m mesh${(table.realisations?.[i] ?? 1) > 1 ? ` (mean over ${table.realisations[i]} realisations)` : ""}`,
      format: (v) => num(v), cellClass: () => (isRef(s) ? "mesh-ref" : ""),
    })),
    { key: "order", label: "Order", num: true, sep: true, value: (r) => r.estimate?.order ?? null, format: (v, r) => orderCell(r.estimate), title: "Observed order of convergence of the three finest meshes (~: oscillatory)" },
    { key: "ext", label: "Extrapolated", num: true, value: (r) => r.estimate?.extrapolated ?? null, format: (v) => num(v), title: "Richardson-extrapolated value (element size → 0)" },
    { key: "gci", label: "GCI (%)", num: true, value: (r) => r.estimate?.gci_fine ?? null, format: (v) => (v === null ? "–" : fmt(100 * v, 3)), title: "Grid convergence index of the finest mesh, in percent of its value" },
    { key: "at", label: `${fmt(ref)} m vs extrapolated (%)`, num: true, value: (r) => r.at_reference, format: (v) => pct(v, 1), title: `The ${fmt(ref)} m mesh's distance from the extrapolated value, in percent of it` },
  ];
  const rows = [...table.rows].map((r, i) => [r, i])
    .sort(([a, i], [b, j]) => (GROUP_ORDER[a.group] ?? 9) - (GROUP_ORDER[b.group] ?? 9) || i - j)
    .map(([r]) => r);
  return dataTable(cols, rows, { caption, className: "table-scroll mesh-table", rowClass: (r) => `mesh-row mesh-${r.group}` });
}

function quantitySelect(id, quantities, selected, onChange) {
  const groups = [...new Set(quantities.map((q) => q.group))];
  const sel = h("select", { id, onchange: () => onChange(sel.value) },
    groups.map((g) => h("optgroup", { label: GROUP_NAMES[g] || g },
      quantities.filter((q) => q.group === g).map((q) => h("option", { value: q.key, selected: q.key === selected }, `${q.label} (${unitText(q.unit)})`)))));
  return h("label", { for: id }, "Quantity against element size", sel);
}

const tableKey = (t) => `${t.axis}|${meshGroupLabel(t.group)}`;

/**
 * The "Mesh convergence" section of a study: `update(tables)` with the study's
 * tables.mesh_convergence (non-empty); one select of the quantity for every table.
 */
export function meshSection() {
  const controls = h("div", { class: "controls" });
  const blocksEl = h("div", { class: "mesh-blocks" });
  const intro = h("p", { class: "small muted" });
  const el = h("section", { class: "card mesh-section", id: "study-mesh", "aria-labelledby": "study-mesh-title" },
    h("h2", { id: "study-mesh-title" }, "Mesh convergence"), intro, controls, blocksEl);
  const blocks = new Map(); // table key → {card, el, verdict, tableBox, note}
  let tables = [];
  let quantity = null;
  let keys = "";

  function block(t, i) {
    const key = tableKey(t);
    let b = blocks.get(key);
    if (b) return b;
    const title = `${BODY_NAMES[t.body] || t.body} element size: ${meshGroupLabel(t.group)}`;
    const headingId = `mesh-table-${i}-title`;
    const card = plotCard({
      title: "Against element size", id: `mesh-plot-${i}`, height: 360, csvName: `mesh convergence ${meshGroupLabel(t.group)}`,
      description: `The chosen quantity against element size, ${meshGroupLabel(t.group)}: each mesh, the extrapolated value dashed, the finest mesh's GCI shaded`,
      csv: () => ({
        header: ["quantity", "label", "unit", "element size (m)", "value", "realisations", "extrapolated", "order", "GCI fine (-)", "oscillatory"],
        rows: b.table.rows.flatMap((r) => b.table.sizes_m.map((s, k) => [r.key, r.label, r.unit, s, r.values[k], b.table.realisations?.[k], r.estimate?.extrapolated, r.estimate?.order, r.estimate?.gci_fine, r.estimate?.oscillatory])),
      }),
    });
    const verdict = h("p", { class: "mesh-verdict" });
    const tableBox = h("div");
    const meta = h("p", { class: "small muted mesh-meta" });
    const node = h("div", { class: "mesh-block", id: `mesh-table-${i}`, "aria-labelledby": headingId, role: "group" },
      h("h3", { id: headingId }, title), verdict, meta, card.el, tableBox);
    b = { card, el: node, verdict, tableBox, meta, table: t };
    blocks.set(key, b);
    return b;
  }

  async function draw(b) {
    const row = b.table.rows.find((r) => r.key === quantity);
    if (!row) {
      b.card.empty("This group has no value of the chosen quantity.");
      b.card.setNote("");
      return;
    }
    const fig = meshFigure(b.table, row);
    await b.card.draw(fig.data, fig.layout);
    const est = row.estimate;
    const ref = b.table.reference_size_m;
    const many = (b.table.realisations || []).some((n) => n > 1);
    const parts = [`Markers: ${row.label} on each mesh${many ? " (means over the irregularity realisations)" : ""}; ◆ the judged ${fmt(ref)} m.`];
    if (est) {
      const order = est.order === null || est.order === undefined ? "no observed order" : `${est.order_assumed ? "assumed" : "observed"} order ${est.order.toFixed(2)}${est.oscillatory ? ", oscillatory" : ""}`;
      parts.push(`Dashed: the Richardson-extrapolated value from the ${est.sizes_m.length} finest meshes (${est.sizes_m.map((s) => fmt(s)).join(", ")} m; ${order}); shaded: ± the GCI of the finest mesh.`);
      if (row.at_reference !== null && row.at_reference !== undefined) parts.push(`${fmt(ref)} m is ${pct(row.at_reference, 1)} from the extrapolated value.`);
    } else parts.push("No estimate: fewer than two meshes with a value.");
    b.card.setNote(parts.join(" "));
  }

  function renderControls() {
    const qs = meshQuantities(tables);
    if (!qs.some((q) => q.key === quantity)) quantity = (qs.find((q) => q.group === "force") || qs[0])?.key ?? null;
    setChildren(controls, qs.length ? quantitySelect("mesh-quantity", qs, quantity, (v) => {
      quantity = v;
      drawAll();
    }) : null);
  }

  function drawAll() {
    return Promise.all([...blocks.values()].filter((b) => b.el.isConnected).map((b) => draw(b)));
  }

  return {
    el,
    /** Show the study's mesh-convergence tables (and keep the chosen quantity). */
    async update(next) {
      tables = next || [];
      const nowKeys = JSON.stringify(tables.map(tableKey));
      if (nowKeys !== keys) { // other groups: new blocks (their ids follow the order)
        keys = nowKeys;
        blocks.forEach((b) => b.card.purge());
        blocks.clear();
      }
      const axes = [...new Set(tables.map((t) => t.axis))];
      const ref = tables[0]?.reference_size_m;
      setChildren(intro, `The jobs differ in the element size (${axes.join(", ")}): per group of the other axes, each quantity on every mesh, the observed order, the Richardson-extrapolated value and the grid convergence index (GCI) of the finest mesh from the three finest meshes (two: the elements' order 2 assumed), and the distance of the judged ${fmt(ref)} m from the extrapolated value. The verdict judges the paper's claim (section 2.1, Fig. 4): the air-spring force grows with the element size, and ${fmt(ref)} m is adequate.`);
      renderControls();
      const shown = tables.map((t, i) => {
        const b = block(t, i);
        b.table = t;
        const text = t.claim?.text || "";
        setChildren(b.verdict, h("strong", {}, "Verdict: "), text ? text.charAt(0).toUpperCase() + text.slice(1) : "not judged", ".");
        const reals = t.realisations || [];
        setChildren(b.meta, `Sizes ${t.sizes_m.map((s) => fmt(s)).join(", ")} m; ${reals.every((n) => n === reals[0]) ? `${reals[0]} job(s) per size` : `jobs per size ${reals.join(", ")}`}.`);
        setChildren(b.tableBox, meshTable(t, { caption: `Every quantity against the ${t.body === "frames" ? "frames'" : "car body's"} element size, ${meshGroupLabel(t.group)} (~: oscillatory convergence; – no value)` }));
        return b.el;
      });
      setChildren(blocksEl, shown);
      await drawAll();
    },
  };
}
