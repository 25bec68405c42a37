// Figures as in the paper: small multiples of a quantity against speed – one panel per condition
// (group) and direction, one colour per point (points.js) in every panel, shared axes – and the
// flexible-against-rigid differences in percent (Table 2) as bars per point.

import { baseLayout } from "./plot.js";
import { pointColor, pointText } from "./points.js";
import { fixed, fmt, pct } from "./dom.js";

const DIR_NAMES = { z: "vertical", y: "lateral", x: "longitudinal" };
const MAX_COLS = 4;
const PANEL_H = 230;

/** The panels of a grid: one per group and direction, directions as row blocks:
 * [{group, dir, row, col}]. */
export function facetPanels(groups, dirs) {
  const cols = Math.min(MAX_COLS, Math.max(1, groups.length));
  const rowsPerDir = Math.ceil(groups.length / cols);
  return dirs.flatMap((dir, di) => groups.map((group, gi) => ({ group, dir, row: di * rowsPerDir + Math.floor(gi / cols), col: gi % cols })));
}

const axisKey = (k, a) => (k === 1 ? `${a}axis` : `${a}axis${k}`);
const axisRef = (k, a) => (k === 1 ? a : `${a}${k}`);

/** Layout of a grid of panels: domains, shared x, y shared within a direction, titles. */
function gridLayout(panels, { yTitle, xTitle, legendTop }) {
  const nRows = Math.max(...panels.map((p) => p.row)) + 1;
  const nCols = Math.max(...panels.map((p) => p.col)) + 1;
  const gx = 0.035;
  const gy = 0.09 / Math.max(1, nRows / 2);
  const layout = baseLayout(xTitle, "", { hovermode: "closest", margin: { l: 64, r: 110, t: legendTop ? 64 : 28, b: 52 } });
  const base = { ...layout.xaxis };
  const baseY = { ...layout.yaxis };
  const firstOfDir = new Map();
  const annotations = [];
  panels.forEach((p, i) => {
    const k = i + 1;
    const x0 = p.col / nCols + (p.col ? gx / 2 : 0);
    const x1 = (p.col + 1) / nCols - (p.col < nCols - 1 ? gx / 2 : 0);
    const y1 = 1 - p.row / nRows - (p.row ? gy / 2 : 0);
    const y0 = 1 - (p.row + 1) / nRows + (p.row < nRows - 1 ? gy / 2 : 0);
    if (!firstOfDir.has(p.dir)) firstOfDir.set(p.dir, k);
    const lastRow = !panels.some((q) => q.col === p.col && q.row > p.row);
    layout[axisKey(k, "x")] = {
      ...base, domain: [x0, x1], anchor: axisRef(k, "y"), matches: k === 1 ? undefined : "x",
      showticklabels: lastRow, title: lastRow ? { text: xTitle, standoff: 4 } : { text: "" },
    };
    layout[axisKey(k, "y")] = {
      ...baseY, domain: [y0, y1], anchor: axisRef(k, "x"),
      matches: firstOfDir.get(p.dir) === k ? undefined : axisRef(firstOfDir.get(p.dir), "y"),
      showticklabels: p.col === 0, title: p.col === 0 ? { text: yTitle(p.dir), standoff: 4 } : { text: "" },
    };
    annotations.push({ text: `<b>${p.group}</b> · ${DIR_NAMES[p.dir] || p.dir}`, xref: "paper", yref: "paper", x: (x0 + x1) / 2, y: y1, xanchor: "center", yanchor: "bottom", showarrow: false, font: { size: 12 } });
  });
  layout.annotations = annotations;
  layout.legend = { orientation: "h", x: 0, y: 1, yanchor: "bottom", xanchor: "left", font: { size: 12 }, ...(legendTop ? { y: 1 + 40 / (nRows * PANEL_H) } : {}) };
  return { layout, nRows };
}

/**
 * Error bars of the 95 % confidence intervals of means over irregularity realisations (a
 * study's ``seeds``), or nothing when no value has one.
 * @param {Array<number|null>|undefined} ci half widths, null where there is one realisation
 * @param {string} color
 */
export function ciBars(ci, color) {
  if (!ci || !ci.some((v) => v !== null && v !== undefined)) return {};
  return { error_y: { type: "data", array: ci.map((v) => v ?? 0), visible: true, color, thickness: 1.2, width: 4 } };
}

/**
 * Small multiples of a quantity against speed.
 * @param {Array} rows study table rows {group, point, direction, speed_kmh[], value[], ci95[]?, job_ids[], fit?}
 * @param {{groups: string[], dirs: string[], groupLabel: Function, catalogue: Map, order: string[],
 *          yTitle: (dir) => string, limits?: Array<[number, string]>, withFit?: boolean,
 *          mode?: string, unit?: string}} o
 * @returns {{data: object[], layout: object, height: number}}
 */
export function facetFigure(rows, o) {
  const groups = o.groups.filter((g) => rows.some((r) => o.groupLabel(r.group) === g));
  const dirs = o.dirs.filter((d) => rows.some((r) => r.direction === d));
  const panels = facetPanels(groups, dirs);
  const { layout, nRows } = gridLayout(panels, { yTitle: o.yTitle, xTitle: "Speed (km/h)", legendTop: true });
  const speeds = rows.flatMap((r) => r.speed_kmh);
  const span = [Math.min(...speeds) - 3, Math.max(...speeds) + 3];
  layout.xaxis.range = span;
  const data = [];
  const legendDone = new Set();
  const shapes = [];
  panels.forEach((p, i) => {
    const k = i + 1;
    const [xa, ya] = [axisRef(k, "x"), axisRef(k, "y")];
    for (const r of rows.filter((x) => x.direction === p.dir && o.groupLabel(x.group) === p.group).sort((a, b) => o.order.indexOf(a.point) - o.order.indexOf(b.point))) {
      const color = pointColor(r.point);
      const desc = pointText(r.point, o.catalogue);
      const fitOk = o.withFit && r.fit && r.fit.slope !== null && r.fit.slope !== undefined;
      data.push({
        type: "scatter", mode: o.mode || "lines+markers", name: r.point, legendgroup: r.point, showlegend: !legendDone.has(r.point),
        x: r.speed_kmh, y: r.value, customdata: r.job_ids, xaxis: xa, yaxis: ya,
        marker: { color, size: 7 }, line: { color, width: 1.6 }, ...ciBars(r.ci95, color),
        hovertemplate: `${desc}<br>${p.group}, ${DIR_NAMES[p.dir]}<br>%{x} km/h: %{y:.3f}${o.unit ? ` ${o.unit}` : ""}${fitOk ? `<br>fit R² = ${fixed(r.fit.r_squared, 3)}` : ""}<br>click to open the job<extra></extra>`,
      });
      legendDone.add(r.point);
      if (fitOk) {
        const x0 = Math.min(...r.speed_kmh);
        const x1 = Math.max(...r.speed_kmh);
        data.push({
          type: "scatter", mode: "lines", name: `fit ${r.point}`, legendgroup: r.point, showlegend: false, hoverinfo: "skip", xaxis: xa, yaxis: ya,
          x: [x0, x1], y: [r.fit.slope * x0 + r.fit.intercept, r.fit.slope * x1 + r.fit.intercept], line: { color, dash: "dash", width: 1.2 },
        });
      }
    }
    for (const [y, text] of o.limits || []) {
      shapes.push({ type: "line", xref: `${xa} domain`, yref: ya, x0: 0, x1: 1, y0: y, y1: y, line: { color: "#9aa3ad", dash: "dot", width: 1 } });
      if (p.col === Math.max(...panels.filter((q) => q.row === p.row).map((q) => q.col))) {
        layout.annotations.push({ xref: "paper", yref: ya, x: layout[axisKey(k, "x")].domain[1] + 0.005, y, text, showarrow: false, xanchor: "left", yanchor: "middle", font: { size: 10, color: "#52606d" } });
      }
    }
  });
  layout.shapes = shapes;
  for (const key of Object.keys(layout).filter((k) => k.startsWith("yaxis"))) layout[key].rangemode = "tozero"; // both quantities are ≥ 0
  return { data, layout, height: Math.max(320, nRows * PANEL_H + 90) };
}

/**
 * Flexible against rigid as bars: x the points, y the difference in percent of rigid, one
 * panel per direction, the bar in the point's colour (cases told apart by pattern).
 * @param {Array} rows flexible_vs_rigid rows of one quantity
 * @param {{caseLabel: Function, catalogue: Map, order: string[], quantity: string}} o
 */
export function flexRigidFigure(rows, o) {
  const dirs = ["z", "y", "x"].filter((d) => rows.some((r) => r.direction === d));
  const cases = [...new Set(rows.map(o.caseLabel))];
  const PATTERNS = ["", "/", ".", "x", "\\", "+"];
  const panels = dirs.map((dir, i) => ({ group: o.quantity, dir, row: 0, col: i }));
  const { layout } = gridLayout(panels, { yTitle: () => "Flexible − rigid (% of rigid)", xTitle: "Point", legendTop: cases.length > 1 });
  const data = [];
  panels.forEach((p, i) => {
    const k = i + 1;
    layout[axisKey(k, "x")].type = "category";
    layout[axisKey(k, "x")].matches = undefined;
    layout[axisKey(k, "x")].categoryorder = "array";
    layout[axisKey(k, "x")].categoryarray = o.order;
    layout[axisKey(k, "y")].zeroline = true;
    layout[axisKey(k, "y")].zerolinecolor = "#52606d";
    cases.forEach((c, ci) => {
      const sel = rows.filter((r) => r.direction === p.dir && o.caseLabel(r) === c).sort((a, b) => o.order.indexOf(a.point) - o.order.indexOf(b.point));
      if (!sel.length) return;
      data.push({
        type: "bar", name: c, legendgroup: c, showlegend: cases.length > 1 && i === 0, offsetgroup: c,
        x: sel.map((r) => r.point), y: sel.map((r) => (r.relative === null ? null : 100 * r.relative)),
        xaxis: axisRef(k, "x"), yaxis: axisRef(k, "y"),
        marker: { color: sel.map((r) => pointColor(r.point)), pattern: { shape: PATTERNS[ci % PATTERNS.length], fgcolor: "#fff" } },
        text: sel.map((r) => (r.relative === null ? "" : pct(r.relative))), textposition: "outside", cliponaxis: false, textfont: { size: 11 },
        ...ciBars(sel.map((r) => (r.relative_ci95 == null ? null : 100 * r.relative_ci95)), "#1f2933"),
        customdata: sel.map((r) => [pointText(r.point, o.catalogue), fmt(r.rigid, 3), fmt(r.flexible, 3)]),
        hovertemplate: `%{customdata[0]}<br>${c}, ${DIR_NAMES[p.dir]}<br>rigid %{customdata[1]}, flexible %{customdata[2]}: %{y:+.1f} %<extra></extra>`,
      });
    });
  });
  for (let k = 2; k <= panels.length; k += 1) layout[axisKey(k, "y")].matches = "y"; // one scale for both directions
  layout.barmode = "group";
  layout.uniformtext = { mode: "show", minsize: 11 };
  layout.showlegend = cases.length > 1;
  layout.margin = { ...layout.margin, r: 16 };
  return { data, layout };
}
