// The measuring points of the car body: one colour per point across every chart, the one-line
// description and position wherever a point name appears (tooltip), and a small drawing of the
// car body (side and plan view) with the paper's points and the user's points.
//
// Descriptions and positions come from the service, never from constants here: a run's recorded
// points (GET /jobs/{id}/channels `points`: name, description, x, y, z, on_floor, kind) or, where
// no run is at hand, the paper's list (GET /schemas/points: name, description, along, across,
// level). Both are read from flexride.vehicle.topology.PAPER_POINTS on the server.

import { api, cached } from "../api.js";
import { h, fmt } from "./dom.js";

/** Colours of the paper's points in the order of GET /schemas/points (Okabe–Ito), then of the
 * other points (user points) by a stable hash of their name. */
const PAPER_COLORS = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9"];
const OTHER_COLORS = ["#000000", "#7F3C8D", "#3969AC", "#80BA5A", "#E73F74", "#8C6D31"];

let paperList = [];
const paperIndex = new Map();

/** Load the paper's points once (GET /schemas/points); resolves to the list. */
export async function loadPaperPoints() {
  const list = await cached("paper-points", api.paperPoints);
  if (!paperList.length) {
    paperList = list;
    list.forEach((p, i) => paperIndex.set(p.name, i));
  }
  return list;
}

/** The paper's points as loaded (empty before loadPaperPoints resolves). */
export function paperPoints() {
  return paperList;
}

/** Paper point names in their order, then the others sorted. */
export function pointOrder(names) {
  const set = new Set(names);
  return [...paperList.map((p) => p.name).filter((n) => set.has(n)), ...[...set].filter((n) => !paperIndex.has(n)).sort()];
}

function hash(s) {
  let x = 0;
  for (const c of String(s)) x = (x * 31 + c.charCodeAt(0)) >>> 0;
  return x;
}

/** The colour of a point, the same in every chart of the dashboard. */
export function pointColor(name) {
  const i = paperIndex.get(name);
  if (i !== undefined && i < PAPER_COLORS.length) return PAPER_COLORS[i];
  return OTHER_COLORS[hash(name) % OTHER_COLORS.length];
}

/** The description of a point without the "NAME: " its recorded form starts with. */
function plainDescription(p) {
  const d = String(p?.description || "");
  return p?.name && d.startsWith(`${p.name}: `) ? d.slice(p.name.length + 2) : d;
}

/** A catalogue name → {name, description, x?, y?, z?, kind?, on_floor?} from a run's recorded
 * points (positions) over the paper's list (descriptions only). */
export function pointCatalogue(recorded = []) {
  const out = new Map();
  for (const p of paperList) out.set(p.name, { name: p.name, description: p.description, kind: "paper", on_floor: p.level === "floor" });
  for (const p of recorded || []) {
    if (p.body && p.body !== "carbody") continue;
    out.set(p.name, { ...p, description: plainDescription(p) });
  }
  return out;
}

/** Position text "x 6.3 m, y 0 m, z 3.8 m" of a point with a position, else "". */
export function positionText(p) {
  if (!p || typeof p.x !== "number") return "";
  return `x ${fmt(p.x, 3)} m, y ${fmt(p.y, 3)} m, z ${fmt(p.z, 3)} m`;
}

/** One line for people: "PC: floor at the car-body centre (x 0 m, y 0 m, z 1.1 m)". */
export function pointText(name, catalogue) {
  const p = catalogue?.get(name);
  if (!p) return name;
  const pos = positionText(p);
  return `${name}: ${p.description || "recorded point"}${pos ? ` (${pos})` : ""}`;
}

/** A point name with its colour and its description and position as tooltip. */
export function pointTag(name, catalogue) {
  return h("abbr", { class: "pt", title: pointText(name, catalogue), dataset: { point: name } },
    h("span", { class: "pt-swatch", style: { background: pointColor(name) }, "aria-hidden": "true" }), name);
}

// -- drawing --------------------------------------------------------------------------------------

const SVG = "http://www.w3.org/2000/svg";
function s(tag, attrs = {}, ...children) {
  const el = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) if (v !== null && v !== undefined) el.setAttribute(k, String(v));
  for (const c of children.flat()) if (c !== null && c !== undefined) el.append(c instanceof Node ? c : document.createTextNode(String(c)));
  return el;
}

/** Extent of the drawn car body (m) around the points: half length and half width, floor and
 * roof height. Schematic: the car body's outline is not part of the scenario. */
function extent(pts) {
  const xs = pts.map((p) => Math.abs(p.x));
  const ys = pts.map((p) => Math.abs(p.y));
  const zs = pts.map((p) => p.z);
  return {
    hx: Math.max(9.5, ...xs.map((x) => x + 0.8)),
    hy: Math.max(1.4, ...ys.map((y) => y + 0.2)),
    floor: Math.min(1.1, ...zs),
    roof: Math.max(3.8, ...zs),
  };
}

/** Bogie centres: the x of the paper's points above them (front and rear), else ±6.3 m. */
function bogieXs(pts) {
  const above = pts.filter((p) => p.kind === "paper" && Math.abs(p.y) < 1e-9 && Math.abs(p.x) > 1);
  const xs = [...new Set(above.map((p) => p.x))];
  return xs.length ? xs : [6.3, -6.3];
}

function marker(p, X, Y, r) {
  const c = pointColor(p.name);
  const title = s("title", {}, pointText(p.name, new Map([[p.name, p]])));
  if (p.kind === "paper") return s("circle", { cx: X, cy: Y, r, fill: c, stroke: "#fff", "stroke-width": 1.2, class: "pt-mark", "data-point": p.name }, title);
  return s("rect", { x: X - r, y: Y - r, width: 2 * r, height: 2 * r, fill: c, stroke: "#fff", "stroke-width": 1.2, class: "pt-mark", "data-point": p.name }, title);
}

/** Labels of points that share a drawn position are joined ("PFB/PR"). */
function labelled(pts, key) {
  const groups = new Map();
  for (const p of pts) {
    const k = key(p);
    if (!groups.has(k)) groups.set(k, []);
    groups.get(k).push(p);
  }
  return [...groups.values()];
}

/**
 * The car body from the side (x–z) and from above (x–y) with the points marked: the paper's as
 * circles, the user's as squares, in the colours of the charts; each with its description and
 * position as tooltip. Front (x > 0) to the right, left (y > 0) up in the plan view.
 * @param {Array<{name: string, x: number, y: number, z: number, kind?: string, description?: string}>} points
 */
export function carbodyDrawing(points) {
  const pts = (points || []).filter((p) => typeof p.x === "number" && p.kind !== "grid");
  const e = extent(pts);
  const W = 560;
  const pad = 28;
  const sx = (W - 2 * pad) / (2 * e.hx);
  const X = (x) => pad + (x + e.hx) * sx;
  const sideH = (e.roof + 0.3) * sx;
  const side0 = 18 + sideH; // rail level
  const Zs = (z) => side0 - z * sx;
  const planTop = side0 + 44;
  const planH = 2 * e.hy * sx;
  const Yp = (y) => planTop + (e.hy - y) * sx;
  const Hsvg = planTop + planH + 26;
  const bogies = bogieXs(pts);
  const kids = [];
  // side view: car body, bogies, wheels, rail
  kids.push(s("text", { x: pad, y: 12, class: "pt-cap" }, "Side view (x–z)"));
  kids.push(s("rect", { x: X(-e.hx), y: Zs(e.roof), width: 2 * e.hx * sx, height: (e.roof - e.floor) * sx, class: "pt-body" }));
  kids.push(s("line", { x1: X(-e.hx) - 6, x2: X(e.hx) + 6, y1: side0, y2: side0, class: "pt-rail" }));
  for (const bx of bogies) {
    kids.push(s("rect", { x: X(bx - 1.6), y: Zs(e.floor * 0.62), width: 3.2 * sx, height: e.floor * 0.28 * sx, class: "pt-bogie" }));
    for (const wx of [bx - 1.1, bx + 1.1]) kids.push(s("circle", { cx: X(wx), cy: side0 - 0.42 * sx, r: 0.42 * sx, class: "pt-wheel" }));
  }
  for (const group of labelled(pts, (p) => `${p.x.toFixed(2)},${p.z.toFixed(2)}`)) {
    const p0 = group[0];
    group.forEach((p) => kids.push(marker(p, X(p.x), Zs(p.z), 5)));
    kids.push(s("text", { x: X(p0.x) + 7, y: Zs(p0.z) - 6, class: "pt-label" }, group.map((p) => p.name).join("/")));
  }
  // plan view: outline, bogie centres, centre line
  kids.push(s("text", { x: pad, y: planTop - 8, class: "pt-cap" }, "Plan view (x–y), left side up"));
  kids.push(s("rect", { x: X(-e.hx), y: Yp(e.hy), width: 2 * e.hx * sx, height: planH, class: "pt-body" }));
  kids.push(s("line", { x1: X(-e.hx), x2: X(e.hx), y1: Yp(0), y2: Yp(0), class: "pt-centre" }));
  for (const bx of bogies) kids.push(s("line", { x1: X(bx), x2: X(bx), y1: Yp(e.hy), y2: Yp(-e.hy), class: "pt-centre" }));
  for (const group of labelled(pts, (p) => `${p.x.toFixed(2)},${p.y.toFixed(2)}`)) {
    const p0 = group[0];
    group.forEach((p) => kids.push(marker(p, X(p.x), Yp(p.y), 5)));
    kids.push(s("text", { x: X(p0.x) + 7, y: Yp(p0.y) + (p0.y < 0 ? 14 : -6), class: "pt-label" }, group.map((p) => p.name).join("/")));
  }
  kids.push(s("text", { x: X(e.hx), y: Hsvg - 6, class: "pt-cap", "text-anchor": "end" }, "front (x > 0) →"));
  return s("svg", { viewBox: `0 0 ${W} ${Hsvg}`, class: "pt-drawing", role: "img", "aria-label": `Car body from the side and from above with the measuring points ${pts.map((p) => p.name).join(", ")}` }, ...kids);
}

/** A table of the points: name, description, position (m) and floor / roof. */
function pointTable(pts) {
  return h("table", { class: "data pt-table" },
    h("caption", { class: "sr-only" }, "Measuring points"),
    h("thead", {}, h("tr", {}, ["Point", "Where", "x (m)", "y (m)", "z (m)"].map((t, i) => h("th", { scope: "col", class: i > 1 ? "num" : "" }, t)))),
    h("tbody", {}, pts.map((p) => h("tr", { dataset: { point: p.name } },
      h("th", { scope: "row" }, h("span", { class: "pt-swatch", style: { background: pointColor(p.name) }, "aria-hidden": "true" }), p.name),
      h("td", {}, p.description || (p.kind === "user" ? "user point" : "")),
      ["x", "y", "z"].map((k) => h("td", { class: "num" }, typeof p[k] === "number" ? fmt(p[k], 3) : "–"))))));
}

/**
 * A card with the drawing and the legend of the points (name, description, position).
 * @param {Map} catalogue from pointCatalogue
 * @param {{id?: string, open?: boolean, note?: string}} opts
 */
export function pointsCard(catalogue, { id = "points-card", open = true, note = "" } = {}) {
  const pts = [...catalogue.values()].filter((p) => p.kind !== "grid");
  const withPos = pts.filter((p) => typeof p.x === "number");
  return h("details", { class: "card points-card", id, open },
    h("summary", {}, h("strong", {}, "Measuring points"), h("span", { class: "muted small" }, ` – ${pts.map((p) => p.name).join(", ")}`)),
    h("div", { class: "points-layout" },
      withPos.length ? carbodyDrawing(withPos) : null,
      h("div", {}, pointTable(pts),
        h("p", { class: "help" }, "Car-body coordinates: x from the car-body centre, forward positive; y left positive; z above top of rail. Circles: the paper's points; squares: your own points (output.points).", note ? ` ${note}` : ""))));
}
