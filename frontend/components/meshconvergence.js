// Mesh convergence of a study (issue 33: the paper's element-size pre-calculation, Fig. 4): for
// each table of GET /studies/{id} → tables.mesh_convergence (one per body and group of the
// other axes) the claim's verdict with its two parts as badges, the chosen quantity against
// element size with the converged estimate (Richardson's extrapolation where reliable, else the
// finest mesh's value) and its band, and a table of every quantity, the rows below the
// resolution greyed and not judged. The numbers are the service's
// (flexride.study.mesh_convergence, mesh_verdict); nothing is estimated here.

import { h, setChildren, fmt, pct, prettyUnit, dataTable } from "./dom.js";
import { plotCard, baseLayout, COLORS } from "./plot.js";

const GROUP_ORDER = { force: 0, frequency: 1, comfort: 2 };
const GROUP_NAMES = { force: "Air-spring forces", frequency: "Elastic frequencies", comfort: "Comfort" };
const BODY_NAMES = { carbody: "Car body", frames: "Bogie frames" };
const OSCILLATORY = "Oscillatory convergence: the differences between the meshes change sign, so the spread of the values, not an asymptote, bounds the error; not reliable: the converged estimate is the finest mesh's value, its band the spread of the finest meshes";
const SLOW = "Observed order below 0.5: the differences between the meshes hardly shrink and Richardson's extrapolation would run far beyond the data; not reliable: the converged estimate is the finest mesh's value, its band the spread of the finest meshes";
const NO_ORDER = "No observed order: the finest values are equal or do not converge monotonically; the converged estimate is the finest mesh's value, its band the spread of the finest meshes";

/** Significant digits of a value: 4 (e.g. 5.150 Hz, 1.980, 100.0 N). */
const num = (v) => fmt(v, 4);
const unitText = (u) => (u === "-" ? "–" : prettyUnit(u));

/** "smooth-straight · 80 km/h · flexible body": the other axes' values in the service's order
 * (the jobs' axis order: condition, speed, body model, then parameters). */
export function meshGroupLabel(group) {
  const g = group || {};
  const text = (k, v) => {
    if (k === "speed_kmh") return `${fmt(Number(v))} km/h`;
    if (k === "body_model") return `${v} body`;
    if (k === "condition") return String(v);
    return `${k.split(".").pop().replace(/_/g, " ")} ${typeof v === "number" ? fmt(v, 4) : v}`;
  };
  return Object.keys(g).map((k) => text(k, g[k])).join(" · ") || "all jobs";
}

/** The default quantity: the first force row judged (not below the resolution) in every table
 * that has it, else in any table, else the first force row (else the first quantity). */
export function defaultMeshQuantity(tables, quantities) {
  const forces = quantities.filter((q) => q.group === "force");
  const rowsOf = (key) => tables.map((t) => (t.rows || []).find((r) => r.key === key)).filter(Boolean);
  const everywhere = forces.find((q) => rowsOf(q.key).every((r) => !r.negligible));
  const anywhere = forces.find((q) => rowsOf(q.key).some((r) => !r.negligible));
  return (everywhere || anywhere || forces[0] || quantities[0])?.key ?? null;
}

/** Why the estimate is not reliable, in a few words (null where it is). */
function unreliableWhy(est) {
  if (!est || est.reliable) return null;
  if (est.oscillatory) return "the meshes oscillate";
  if (Number.isFinite(est.order)) return "the meshes converge slower than order 0.5";
  return "the meshes give no observed order";
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

/** The figure of one row: the value per mesh (markers), the converged estimate (dashed) and its
 * band (± band × |converged|, shaded), the judged size marked; a row below the resolution has
 * its markers only. */
export function meshFigure(table, row) {
  const sizes = table.sizes_m;
  const ref = table.reference_size_m;
  const unit = unitText(row.unit);
  const pts = sizes.map((s, i) => [s, row.values[i], table.realisations?.[i] ?? 1]).filter(([, v]) => v !== null && v !== undefined);
  const xmax = Math.max(...sizes) * 1.06;
  const est = row.negligible ? null : row.estimate;
  const data = [];
  const conv = est?.converged;
  const band = est?.band;
  if (est && Number.isFinite(band) && Number.isFinite(conv)) {
    const half = band * Math.abs(conv);
    const what = est.reliable ? `GCI of the finest mesh (${fmt(est.sizes_m[0])} m)` : `spread of the ${est.sizes_m.length} finest meshes`;
    data.push({
      type: "scatter", mode: "lines", meta: "band", fill: "toself", fillcolor: "rgba(0,114,178,0.14)",
      line: { width: 0 }, hoverinfo: "skip",
      name: `band, ${what}: ±${fmt(100 * band, 3)} %`,
      x: [0, xmax, xmax, 0, 0], y: [conv - half, conv - half, conv + half, conv + half, conv - half],
    });
  }
  if (est && Number.isFinite(conv)) {
    const how = est.reliable ? "Richardson's extrapolation (h → 0)" : "the finest mesh's value";
    data.push({
      type: "scatter", mode: "lines", meta: "converged", line: { color: COLORS[1], dash: "dash", width: 2 },
      name: `converged estimate: ${num(conv)} ${unit}`,
      x: [0, xmax], y: [conv, conv],
      hovertemplate: `converged estimate, ${how}: ${num(conv)} ${unit}<extra></extra>`,
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

const notJudged = (r) => h("span", { class: "mesh-nj-dash", title: `Below the resolution, not judged: ${r.negligible}` }, "–");

function orderCell(r) {
  const est = r.estimate;
  if (r.negligible) return notJudged(r);
  if (!est) return h("span", { title: "No estimate: fewer than two meshes with a value" }, "–");
  if (est.order === null || est.order === undefined || !Number.isFinite(est.order)) {
    return h("span", { class: est.reliable ? "" : "mesh-unreliable", title: NO_ORDER }, "–");
  }
  const text = `${est.order.toFixed(2)}${est.order_assumed ? " (assumed)" : ""}`;
  if (est.oscillatory) return h("span", { class: "mesh-osc mesh-unreliable", title: OSCILLATORY }, `~${text}`);
  if (!est.reliable) return h("span", { class: "mesh-slow mesh-unreliable", title: SLOW }, `${text}?`);
  return h("span", { title: est.order_assumed ? "Two meshes only: the elements' order 2 is assumed (Roache's safety factor 3)" : "Observed order of convergence of the three finest meshes" }, text);
}

function convergedCell(v, r) {
  if (r.negligible) return notJudged(r);
  if (v === null || v === undefined) return "–";
  const est = r.estimate;
  return h("span", { title: est.reliable ? "Richardson's extrapolation of the finest meshes (h → 0)" : `The finest mesh's value (${fmt(est.sizes_m[0])} m): ${unreliableWhy(est)}` }, num(v));
}

/** The label cell: the quantity, and for a row below the resolution a small "not judged" with
 * the service's reason as its title. */
function labelCell(v, r) {
  if (!r.negligible) return v;
  return h("span", { title: `Below the resolution, not judged: ${r.negligible}` }, v, " ",
    h("span", { class: "mesh-nj small" }, "(not judged)"));
}

/** The table of every quantity of one mesh-convergence table. */
export function meshTable(table, { caption } = {}) {
  const sizes = table.sizes_m;
  const ref = table.reference_size_m;
  const isRef = (s) => Math.abs(s - ref) < 1e-9;
  const cols = [
    { key: "label", label: "Quantity", format: labelCell },
    { key: "unit", label: "Unit", format: (v) => unitText(v) },
    ...sizes.map((s, i) => ({
      key: `v${i}`, label: `${fmt(s)} m`, num: true, sep: i === 0, value: (r) => r.values[i],
      title: `${isRef(s) ? "The judged size; " : ""}the value on the ${fmt(s)} m mesh${(table.realisations?.[i] ?? 1) > 1 ? ` (mean over ${table.realisations[i]} realisations)` : ""}`,
      format: (v) => num(v), cellClass: () => (isRef(s) ? "mesh-ref" : ""),
    })),
    { key: "order", label: "Order", num: true, sep: true, value: (r) => (r.negligible ? null : r.estimate?.order ?? null), format: (v, r) => orderCell(r), title: "Observed order of convergence of the three finest meshes (~: oscillatory, ?: below 0.5 — both not reliable: the converged estimate is then the finest mesh's value)" },
    { key: "conv", label: "Converged", num: true, value: (r) => (r.negligible ? null : r.estimate?.converged ?? null), format: convergedCell, title: "Best estimate of the converged value: Richardson's extrapolation where reliable, else the finest mesh's value" },
    { key: "band", label: "Band (%)", num: true, value: (r) => (r.negligible ? null : r.estimate?.band ?? null), format: (v, r) => (r.negligible ? notJudged(r) : v === null || v === undefined ? "–" : fmt(100 * v, 3)), title: "Relative uncertainty of the converged estimate, in percent of it: the finest mesh's GCI where reliable, else the spread of the three finest meshes" },
    { key: "at", label: `${fmt(ref)} m vs converged (%)`, num: true, value: (r) => (r.negligible ? null : r.at_reference), format: (v, r) => (r.negligible ? notJudged(r) : pct(v, 1)), title: `The ${fmt(ref)} m mesh's distance from the converged estimate, in percent of it (rows below the resolution: not judged)` },
  ];
  const rows = [...table.rows].map((r, i) => [r, i])
    .sort(([a, i], [b, j]) => (GROUP_ORDER[a.group] ?? 9) - (GROUP_ORDER[b.group] ?? 9) || i - j)
    .map(([r]) => r);
  return dataTable(cols, rows, { caption, className: "table-scroll mesh-table", rowClass: (r) => `mesh-row mesh-${r.group}${r.negligible ? " mesh-negligible" : ""}` });
}

function quantitySelect(id, quantities, selected, onChange) {
  const groups = [...new Set(quantities.map((q) => q.group))];
  const sel = h("select", { id, onchange: () => onChange(sel.value) },
    groups.map((g) => h("optgroup", { label: GROUP_NAMES[g] || g },
      quantities.filter((q) => q.group === g).map((q) => h("option", { value: q.key, selected: q.key === selected }, `${q.label} (${unitText(q.unit)})`)))));
  return h("label", { for: id }, "Quantity against element size", sel);
}

const tableKey = (t) => `${t.axis}|${meshGroupLabel(t.group)}`;

const yesNo = (v) => (v === true ? "yes" : v === false ? "no" : "not judged");

/** The claim's two parts as badges: "force grows: yes/no/not judged", "0.2 m adequate: …". */
export function claimBadges(claim, ref) {
  const c = claim || {};
  const [n, of] = c.grows || [0, 0];
  const within = c.reference_within || {};
  const growsTitle = c.grows_holds === null || c.grows_holds === undefined
    ? "No air-spring force row is large enough to judge growth"
    : `The paper's claim that the air-spring force grows with the element size: ${n} of ${of} judged force rows grow (monotonically, by at least 1 %) from ${fmt(ref)} m to the coarsest mesh`;
  const adequateTitle = c.adequate === null || c.adequate === undefined
    ? `${fmt(ref)} m is not among the sizes, or no row is large enough to judge`
    : `${fmt(ref)} m within 5 % of the converged estimate of every judged row: at most ${fmt(100 * within.all, 3)} %`;
  const one = (name, cls, value, title) => h("span", { class: `badge mesh-claim mesh-claim-${cls} mesh-${yesNo(value).replace(" ", "-")}`, title }, `${name}: ${yesNo(value)}`);
  return h("p", { class: "mesh-badges" },
    one("force grows", "grows", c.grows_holds, growsTitle),
    one(`${fmt(ref)} m adequate`, "adequate", c.adequate, adequateTitle));
}

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
      description: `The chosen quantity against element size, ${meshGroupLabel(t.group)}: each mesh, the converged estimate dashed, its band shaded`,
      csv: () => ({
        header: ["quantity", "label", "unit", "element size (m)", "value", "realisations", "converged", "band (-)", "reliable", "order", "oscillatory", "extrapolated", "GCI fine (-)", "not judged (below the resolution)"],
        rows: b.table.rows.flatMap((r) => b.table.sizes_m.map((s, k) => [r.key, r.label, r.unit, s, r.values[k], b.table.realisations?.[k], r.estimate?.converged, r.estimate?.band, r.estimate?.reliable, r.estimate?.order, r.estimate?.oscillatory, r.estimate?.extrapolated, r.estimate?.gci_fine, r.negligible || ""])),
      }),
    });
    const verdict = h("div", { class: "mesh-verdict" });
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
    if (row.negligible) {
      parts.push(`Below the resolution, not judged: ${row.negligible}.`);
    } else if (est) {
      const meshes = `the ${est.sizes_m.length} finest meshes (${est.sizes_m.map((s) => fmt(s)).join(", ")} m`;
      const order = est.order === null || est.order === undefined || !Number.isFinite(est.order) ? "no observed order" : `${est.order_assumed ? "assumed" : "observed"} order ${est.order.toFixed(2)}${est.oscillatory ? ", oscillatory" : ""}`;
      const band = Number.isFinite(est.band) ? ` (±${fmt(100 * est.band, 3)} %)` : "";
      if (est.reliable) {
        parts.push(`Dashed: the converged estimate, Richardson's extrapolation from ${meshes}; ${order}); shaded: its band, ± the GCI of the finest mesh${band}.`);
      } else {
        parts.push(`Dashed: the converged estimate, the finest mesh's value; ${unreliableWhy(est)} (${meshes}; ${order}) — band = spread of the finest meshes${band}, shaded.`);
      }
      if (row.at_reference !== null && row.at_reference !== undefined) parts.push(`${fmt(ref)} m is ${pct(row.at_reference, 1)} from the converged estimate.`);
    } else parts.push("No estimate: fewer than two meshes with a value.");
    b.card.setNote(parts.join(" "));
  }

  function renderControls() {
    const qs = meshQuantities(tables);
    if (!qs.some((q) => q.key === quantity)) quantity = defaultMeshQuantity(tables, qs);
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
      setChildren(intro, `The jobs differ in the element size (${axes.join(", ")}): per group of the other axes, each quantity on every mesh, the observed order of the three finest meshes (two: the elements' order 2 assumed), the converged estimate with its band — Richardson's extrapolation and the finest mesh's grid convergence index (GCI) where the meshes converge monotonically at order 0.5 or more, else the finest mesh's value and the spread of the finest meshes — and the distance of the judged ${fmt(ref)} m from the converged estimate. Rows below the resolution (greyed) are not judged. The verdict judges the paper's claim (section 2.1, Fig. 4): the air-spring force grows with the element size, and ${fmt(ref)} m is adequate (within 5 % of every converged estimate).`);
      renderControls();
      const shown = tables.map((t, i) => {
        const b = block(t, i);
        b.table = t;
        const text = t.claim?.text || "";
        setChildren(b.verdict, h("p", { class: "mesh-verdict-text" }, h("strong", {}, "Verdict: "), text ? text.charAt(0).toUpperCase() + text.slice(1) : "not judged", "."),
          claimBadges(t.claim, t.reference_size_m));
        const reals = t.realisations || [];
        setChildren(b.meta, `Sizes ${t.sizes_m.map((s) => fmt(s)).join(", ")} m; ${reals.every((n) => n === reals[0]) ? `${reals[0]} job(s) per size` : `jobs per size ${reals.join(", ")}`}.`);
        setChildren(b.tableBox, meshTable(t, { caption: `Every quantity against the ${t.body === "frames" ? "frames'" : "car body's"} element size, ${meshGroupLabel(t.group)} (~: oscillatory convergence, ?: order below 0.5 — converged = the finest mesh's value, band = spread; greyed: below the resolution, not judged; – no value)` }));
        return b.el;
      });
      setChildren(blocksEl, shown);
      await drawAll();
    },
  };
}
