// Running safety of a job: every wheelset in one table (rows) against every index and wheel
// (columns), the governing value – the highest utilisation of its limit – marked, and the
// headline for the summary card.
//
// Names follow EN 14363 (Q vertical wheel force, Y lateral): each index of the summary carries its
// `symbol` (Y/Q, ΔQ/Q, ΣY) and `title`, and the summary's settings.safety.convention says how GB
// 5599 names the same quantities; both come from flexride.analysis.safety.

import { h, fmt, prettyUnit, dataTable, notice } from "./dom.js";

const ORDER = ["derailment_coefficient", "wheel_unloading", "wheelset_lateral_force"];

/** "wheelset4.left" → {ws: "wheelset4", side: "left"}; "wheelset4" → {ws, side: null}. */
function place(location) {
  const [ws, side] = String(location).split(".");
  return { ws, side: side || null };
}

/** Symbol and title of indices in summaries stored before the summary carried them (jobs run
 * by an older flexride); a summary's own `symbol` and `title` always win. */
const STORED_BEFORE = {
  derailment_coefficient: ["Y/Q", "derailment quotient"],
  wheel_unloading: ["ΔQ/Q", "wheel unloading"],
  wheelset_lateral_force: ["ΣY", "track-shifting force"],
};
const symbolOf = (i) => i.symbol || STORED_BEFORE[i.name]?.[0] || i.name.replace(/_/g, " ");
const titleOf = (i) => i.title || STORED_BEFORE[i.name]?.[1] || i.name.replace(/_/g, " ");
const unitText = (u) => (!u || u === "-" ? "" : ` ${prettyUnit(u)}`);
const wsLabel = (ws) => ws.replace("wheelset", "wheelset ");

/** The index with the highest utilisation, or null. */
export function governing(indices) {
  return (indices || []).reduce((a, b) => ((b.utilisation ?? -1) > (a?.utilisation ?? -1) ? b : a), null);
}

/** {passed, text} of the summary card, or null without indices. */
export function safetyHeadline(summary) {
  const idx = summary?.safety?.indices || [];
  if (!idx.length) return null;
  const g = governing(idx);
  const where = place(g.location);
  return {
    passed: idx.every((i) => i.passed !== false),
    text: `governing: ${symbolOf(g)} at ${wsLabel(where.ws)}${where.side ? ` ${where.side}` : ""}, ${(100 * (g.utilisation ?? 0)).toFixed(1)} % of its limit`,
  };
}

/** Columns of the matrix: one per index and wheel side present, in ORDER. */
function matrixColumns(indices) {
  const cols = [];
  for (const name of ORDER.concat([...new Set(indices.map((i) => i.name))].filter((n) => !ORDER.includes(n)))) {
    const of = indices.filter((i) => i.name === name);
    if (!of.length) continue;
    const sides = [...new Set(of.map((i) => place(i.location).side))].sort((a, b) => String(a).localeCompare(String(b)));
    const limits = [...new Set(of.map((i) => fmt(i.limit, 3)))];
    for (const side of sides) cols.push({ name, side, sample: of[0], limit: limits.length === 1 ? limits[0] : null });
  }
  return cols;
}

function cell(i, gov) {
  if (!i) return "–";
  return h("span", {}, `${fmt(i.value, 3)}${unitText(i.unit)}`,
    h("span", { class: `util${i.passed === false ? " fail" : ""}` }, `${(100 * (i.utilisation ?? 0)).toFixed(0)} %${i === gov ? " · governing" : ""}`));
}

/**
 * The running-safety card of a summary.
 * @param {object} sum the summary (GET /jobs/{id}/summary `summary`)
 * @param {{onWheelset?: (ws: string) => void}} opts a click on a wheelset shows its forces
 */
export function safetyPanel(sum, { onWheelset } = {}) {
  const idx = sum?.safety?.indices || [];
  const title = h("h2", { id: "safety-title" }, "Running safety");
  if (!idx.length) return h("section", { class: "card", "aria-labelledby": "safety-title" }, title, notice("empty", null, sum?.safety?.error || "No running-safety indices in the summary."));
  const gov = governing(idx);
  const cols = matrixColumns(idx);
  const wheelsets = [...new Set(idx.map((i) => place(i.location).ws))].sort();
  const find = (ws, c) => idx.find((i) => i.name === c.name && place(i.location).ws === ws && place(i.location).side === c.side);
  const rows = wheelsets.map((ws) => ({ ws, ...Object.fromEntries(cols.map((c, k) => [`c${k}`, find(ws, c)])) }));
  const govWs = place(gov.location).ws;
  const table = dataTable([
    { key: "ws", label: "Wheelset", format: (v) => (onWheelset ? h("button", { type: "button", class: "btn-quiet btn btn-small", title: `Show the forces of ${wsLabel(v)}`, onclick: () => onWheelset(v) }, wsLabel(v)) : wsLabel(v)) },
    ...cols.map((c, k) => ({
      key: `c${k}`, num: true, label: `${symbolOf(c.sample)}${c.side ? ` ${c.side}` : ""}${c.limit ? ` (≤ ${c.limit}${unitText(c.sample.unit)})` : ""}`,
      title: `${titleOf(c.sample)} ${symbolOf(c.sample)}${c.side ? `, ${c.side} wheel` : ""}: maximum, and its share of the limit`,
      value: (r) => r[`c${k}`]?.value ?? null, format: (v, r) => cell(r[`c${k}`], gov),
      cellClass: (v, r) => (r[`c${k}`] === gov ? "governing" : ""),
    })),
  ], rows, {
    caption: `Every wheelset; governing: ${titleOf(gov)} ${symbolOf(gov)} at ${wsLabel(govWs)}${place(gov.location).side ? ` ${place(gov.location).side}` : ""}, ${(100 * gov.utilisation).toFixed(1)} % of its limit ${fmt(gov.limit, 3)}${unitText(gov.unit)}`,
    className: "safety-matrix-wrap", rowClass: (r) => (r.ws === govWs ? "governing-row" : ""),
  });
  table.querySelector("table").classList.add("safety-matrix");
  table.querySelector("table").id = "safety-matrix";
  const nadal = sum.safety.nadal;
  const convention = sum.settings?.safety?.convention;
  const byName = [...new Map(idx.map((i) => [i.name, i])).values()];
  const passed = idx.every((i) => i.passed !== false);
  return h("section", { class: "card", "aria-labelledby": "safety-title", id: "safety-card" }, title,
    h("p", { class: "help", id: "safety-convention" }, convention || ""),
    h("p", { id: "safety-result" }, h("span", { class: passed ? "pass" : "fail" }, passed ? "passed" : "exceeded"),
      passed ? ": every index of every wheelset within its limit." : `: ${idx.filter((i) => i.passed === false).map((i) => `${symbolOf(i)} at ${i.location}`).join(", ")} beyond the limit.`),
    table,
    nadal ? h("p", { class: "small" }, `Nadal's limit of Y/Q for the wheel's flange angle ${fmt(nadal.flange_angle_deg, 3)}° and μ = ${fmt(nadal.friction, 2)}: ${fmt(nadal.limit, 3)}; largest Y/Q ${fmt(nadal.worst, 3)} at ${nadal.location} (${(100 * nadal.utilisation).toFixed(0)} %, `, h("span", { class: nadal.passed ? "pass" : "fail" }, nadal.passed ? "passed" : "exceeded"), ").") : null,
    h("details", { class: "help" }, h("summary", {}, "How the indices are processed, and every value with its time"),
      h("ul", {}, byName.map((i) => h("li", {}, h("strong", {}, `${titleOf(i)} ${symbolOf(i)}: `),
        String(i.processing || "").replace(/([QP]0|2Q0) = [\d.e+]+ k?N/g, "$1 = static load"), i.standard ? ` (${i.standard})` : ""))),
      dataTable([
        { key: "name", label: "Index", format: (v, r) => `${titleOf(r)} ${symbolOf(r)}` },
        { key: "location", label: "Where" },
        { key: "value", label: "Maximum", num: true, format: (v, r) => `${fmt(v, 3)}${unitText(r.unit)}` },
        { key: "limit", label: "Limit", num: true, format: (v, r) => `${fmt(v, 3)}${unitText(r.unit)}` },
        { key: "utilisation", label: "Utilisation", num: true, format: (v) => (v === null ? "–" : `${(100 * v).toFixed(1)} %`) },
        { key: "passed", label: "Result", format: (v) => (v === null || v === undefined ? "–" : h("span", { class: v ? "pass" : "fail" }, v ? "passed" : "exceeded")) },
        { key: "time_of_max", label: "At (s)", num: true, format: (v) => fmt(v, 4) },
      ], idx, { caption: "Every running-safety index (GB 5599 limits of Y/Q and ΔQ/Q, EN 14363 limit of ΣY)", className: "table-scroll" })));
}
