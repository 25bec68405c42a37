// Channel pickers: a multiple select grouped by body, and point / direction selects.

import { h, prettyUnit, channelLabel, parseChannel, DIRECTION_NAMES } from "./dom.js";

const BODY_ORDER = (b) => (b === "carbody" ? "0" : b.startsWith("frame") ? `1${b}` : b.startsWith("wheelset") ? `2${b}` : `3${b}`);

/** Group channel infos by body, car body first. */
export function groupChannels(channels) {
  const groups = new Map();
  for (const c of channels) {
    const body = c.body || parseChannel(c.name)?.body || c.name;
    if (!groups.has(body)) groups.set(body, []);
    groups.get(body).push(c);
  }
  return [...groups].sort((a, b) => BODY_ORDER(a[0]).localeCompare(BODY_ORDER(b[0])));
}

/** The tooltip of a channel's option: `o.describe(channel)` for car-body channels (the
 * point's description and position), else none. */
function describe(o, c) {
  return o.describe && (c.body || parseChannel(c.name)?.body) === "carbody" ? o.describe({ ...parseChannel(c.name), ...c }) : null;
}

/**
 * <select multiple> of channels with optgroups; onChange(names[]) after each change.
 * @param {{id: string, label: string, channels: object[], selected: string[], max?: number, size?: number, onChange: Function, filter?: Function, describe?: Function}} o
 */
export function channelMultiSelect(o) {
  const chans = o.filter ? o.channels.filter(o.filter) : o.channels;
  const sel = h("select", { id: o.id, multiple: true, size: String(o.size || 9), "aria-describedby": `${o.id}-help` },
    groupChannels(chans).map(([body, list]) => h("optgroup", { label: body === "carbody" ? "car body" : body },
      list.map((c) => h("option", { value: c.name, selected: o.selected.includes(c.name), title: describe(o, c) }, `${c.point ?? ""} ${c.quantity ?? ""} ${c.direction ?? ""} (${prettyUnit(c.unit)})`.trim() || c.name)))));
  const help = h("p", { class: "help", id: `${o.id}-help` }, `Ctrl / Shift + click or Shift + arrows to choose several${o.max ? ` (up to ${o.max})` : ""}.`);
  sel.addEventListener("change", () => {
    let names = [...sel.selectedOptions].map((x) => x.value);
    if (o.max && names.length > o.max) {
      names = names.slice(0, o.max);
      for (const opt of sel.options) opt.selected = names.includes(opt.value);
      help.textContent = `At most ${o.max} channels at once; the first ${o.max} are shown.`;
    }
    o.onChange(names);
  });
  return h("label", { for: o.id, class: "channel-picker" }, o.label, sel, help);
}

/** A single <select> of channels. */
export function channelSelect(o) {
  const chans = o.filter ? o.channels.filter(o.filter) : o.channels;
  const sel = h("select", { id: o.id, onchange: () => o.onChange(sel.value) },
    groupChannels(chans).map(([body, list]) => h("optgroup", { label: body === "carbody" ? "car body" : body },
      list.map((c) => h("option", { value: c.name, selected: c.name === o.selected, title: describe(o, c) }, channelLabel(c.name).replace(/^(car body|\w+ \d) /, "") + ` (${prettyUnit(c.unit)})`)))));
  return h("label", { for: o.id }, o.label, sel);
}

/** A <select> from [value, text] pairs. */
export function simpleSelect(id, label, options, selected, onChange) {
  const sel = h("select", { id, onchange: () => onChange(sel.value) },
    options.map(([v, t]) => h("option", { value: v, selected: String(v) === String(selected) }, t)));
  return h("label", { for: id }, label, sel);
}

export function directionOptions(dirs) {
  return dirs.map((d) => [d, `${DIRECTION_NAMES[d] || d} (${d})`]);
}

/** Car-body points with acceleration channels, in the run's own order (the paper's points,
 * user points, floor grid: GET /jobs/{id}/channels `points`), each with its kind, description,
 * position and floor flag. */
export function accPoints(channels, points) {
  const withAcc = new Set(channels.filter((c) => c.body === "carbody" && c.quantity === "acc").map((c) => c.point));
  return (points || []).filter((p) => p.body === "carbody" && withAcc.has(p.name));
}

/** The point to headline: the paper's floor point nearest the car-body centre (PC), else the
 * first point. */
export function headlinePoint(points) {
  const paperFloor = points.filter((p) => p.kind === "paper" && p.on_floor);
  const pool = paperFloor.length ? paperFloor : points;
  return pool.reduce((best, p) => (best === null || Math.abs(p.x) < Math.abs(best.x) ? p : best), null);
}
