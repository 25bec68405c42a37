// A form generated from the scenario's JSON schema (GET /api/v1/schemas/scenario): the SchemaForm
// class, its groups and its renderers for scalars, enum sets, objects, arrays and discriminated
// unions. Schema reading is in schema.js, inputs in scalarinput.js, checks in validate.js, the
// server's 422 items in servererrors.js, the problem summary in formsummary.js.

import { h } from "./dom.js";
import { clone, resolve, scalarInfo, defaultsOf, freshVariant, variantOf, labelOf, titleOf, plainDescription, unitOf, helpText } from "./schema.js";
import { scalarInput, unitBadge, readScalar, isLongText } from "./scalarinput.js";
import { problems, enumSetProblems, runLengthProblem, RUN_LENGTH_KEYS } from "./validate.js";
import { placeServerErrors, markBlock, blockAt } from "./servererrors.js";
import { showSummary, updateGroupCounts } from "./formsummary.js";
import { pathKey, fieldId, getAt, setAt, deleteAt } from "./valuepath.js";

// Names importable from here before the split.
export { unitOf, plainDescription, humanKey } from "./schema.js";
export { numText } from "./scalarinput.js";

/** Groups of top-level scenario fields, in display order. */
export const GROUPS = [
  { id: "run", label: "Run", keys: ["name", "description", "speed_kmh", "duration_s", "distance_m"], open: true },
  { id: "vehicle", label: "Vehicle", keys: ["vehicle", "bodies"] },
  { id: "track", label: "Track", keys: ["track", "contact"] },
  { id: "line", label: "Line", keys: ["line"] },
  { id: "excitation", label: "Excitation", keys: ["excitation"] },
  { id: "solver", label: "Solver", keys: ["solver"] },
  { id: "output", label: "Outputs", keys: ["output"] },
];

/** The properties of an object node as [key, node, required]. */
const propsOf = (r) => Object.entries(r.properties || {}).map(([k, sub]) => [k, sub, (r.required || []).includes(k)]);

export class SchemaForm {
  /**
   * @param {object} schema JSON schema of a scenario
   * @param {object} value initial scenario
   * @param {{onChange?: (value: object) => void}} opts
   */
  constructor(schema, value, opts = {}) {
    this.schema = schema;
    this.defs = schema.$defs || {};
    this.opts = opts;
    this.value = clone(value) || {};
    this.fields = new Map(); // key → {wrap, input, node, errEl, path, kind}
    this.serverErrors = new Map();
    this.el = h("div", { class: "schema-form" });
    this.render();
  }

  resolve(node) {
    return resolve(this.defs, node);
  }

  scalarInfo(node) {
    return scalarInfo(this.defs, node);
  }

  defaultsOf(node) {
    return defaultsOf(this.defs, node);
  }

  get(path, root = this.value) {
    return getAt(root, path);
  }

  set(path, val) {
    setAt(this.value, path, val);
  }

  /** Set one scalar field's value and show it in its input (no re-render, no change event). */
  setField(path, v) {
    this.set(path, v);
    const key = pathKey(path);
    const f = this.fields.get(key);
    if (f?.kind === "scalar" && f.input && f.input.type !== "checkbox") f.input.value = v ?? "";
    this.validateField(key);
  }

  setValue(value) {
    this.value = clone(value) || {};
    this.serverErrors.clear();
    this.render();
  }

  changed() {
    this.opts.onChange?.(this.value);
  }

  /** After a structural edit (variant or array item): recheck, then tell the owner. */
  restructured() {
    this.validateAll(false);
    this.changed();
  }

  /** Forget the fields under `path` (a block about to be redrawn) that `drop` accepts (all by default). */
  dropFieldsUnder(path, drop = () => true) {
    const prefix = `${pathKey(path)}.`;
    for (const [k, f] of [...this.fields]) if (k.startsWith(prefix) && drop(f)) this.fields.delete(k);
  }

  // -- groups ------------------------------------------------------------------------------

  render() {
    const openState = new Map([...this.el.querySelectorAll("details[data-group]")].map((d) => [d.dataset.group, d.open]));
    this.fields.clear();
    this.summaryEl = h("div", { class: "form-errors", role: "alert", hidden: true });
    const props = this.schema.properties || {};
    const used = new Set();
    const sections = GROUPS.map((g) => {
      const keys = g.keys.filter((k) => props[k]);
      keys.forEach((k) => used.add(k));
      return this.groupSection(g, keys, openState.get(g.id) ?? !!g.open);
    });
    const rest = Object.keys(props).filter((k) => !used.has(k));
    if (rest.length) sections.push(this.groupSection({ id: "other", label: "Other" }, rest, openState.get("other") ?? false));
    this.el.replaceChildren(this.summaryEl, ...sections);
    for (const [k, msg] of this.serverErrors) this.markServer(k, msg);
    this.validateAll(false);
  }

  /** A collapsible group: runs of narrow fields share a grid, blocks stand alone. */
  groupSection(g, keys, open) {
    const body = h("div", { class: "group-body" });
    const count = h("span", { class: "group-errors", "aria-live": "polite" });
    const det = h("details", { class: "group", dataset: { group: g.id }, open },
      h("summary", {}, h("span", { class: "group-title" }, g.label), count), body);
    let grid = null;
    for (const k of keys) {
      const el = this.node(this.schema.properties[k], [k], k, (this.schema.required || []).includes(k));
      if (el.classList.contains("field") && !el.classList.contains("field-wide")) {
        if (!grid) body.append(grid = h("div", { class: "fields" }));
        grid.append(el);
      } else {
        grid = null;
        body.append(el);
      }
    }
    return det;
  }

  // -- renderers ---------------------------------------------------------------------------

  node(node, path, key, required = false) {
    const info = this.scalarInfo(node);
    const r = this.resolve(node);
    if (info.isScalar) return this.scalarField(info, path, key, required);
    if (r.oneOf && r.discriminator) return this.variantBlock(r, path, key);
    if (r.type === "array") return this.arrayBlock(r, path, key);
    if (r.type === "object" || r.properties) return this.objectBlock(r, path, key);
    return this.jsonField(r, path, key);
  }

  objectBlock(r, path, key) {
    const [legend, desc] = labelOf(r, key);
    const fs = h("fieldset", { class: "obj", dataset: { path: pathKey(path) } },
      h("legend", {}, legend),
      desc && path.length > 1 ? h("p", { class: "help" }, desc) : null);
    if (this.get(path) === undefined || this.get(path) === null) this.set(path, {});
    const grid = h("div", { class: "fields" });
    for (const [k, sub, req] of propsOf(r)) grid.append(this.node(sub, [...path, k], k, req));
    fs.append(grid);
    return fs;
  }

  /** A discriminated union: a "Kind" select, and the fields of the chosen variant. */
  variantBlock(r, path, key) {
    const holder = h("div", { class: "variant", dataset: { path: pathKey(path) } });
    const draw = () => {
      const { prop, kind, schema } = variantOf(this.defs, r, this.get(path) || {});
      const fs = h("fieldset", { class: "obj" }, h("legend", {}, titleOf(r, key)),
        this.variantKind(r, path, prop, kind, schema, draw));
      const grid = h("div", { class: "fields" });
      for (const [k, sub, req] of schema ? propsOf(schema) : []) {
        if (k !== prop) grid.append(this.node(sub, [...path, k], k, req));
      }
      fs.append(grid);
      this.dropFieldsUnder(path, (f) => !fs.contains(f.wrap) && (!f.wrap.isConnected || holder.contains(f.wrap)));
      holder.replaceChildren(fs);
    };
    draw();
    return holder;
  }

  /** The "Kind" select of a union; choosing a kind starts that variant from its defaults. */
  variantKind(r, path, prop, kind, schema, redraw) {
    const id = fieldId([...path, prop]);
    const sel = h("select", { id, onchange: () => {
      this.set(path, freshVariant(this.defs, r, sel.value));
      redraw();
      this.restructured();
    } }, Object.keys(r.discriminator.mapping).map((k) => h("option", { value: k, selected: k === kind }, k)));
    const desc = plainDescription(schema);
    const help = `${desc ? `${desc.split("\n")[0].replace(/\.?\s*$/, ".")} ` : ""}One of ${Object.keys(r.discriminator.mapping).join(", ")}; another kind starts from its defaults.`;
    sel.setAttribute("aria-describedby", `${id}-help`);
    return h("div", { class: "field field-wide" }, h("label", { for: id }, "Kind"), sel,
      h("p", { class: "help", id: `${id}-help` }, help));
  }

  /** A list of items with Remove and Add buttons (a list of enum strings is a set of checkboxes). */
  arrayBlock(r, path, key) {
    const items = this.resolve(r.items || {});
    if (items.enum && items.type === "string") return this.enumSet(r, items, path, key);
    const holder = h("div", { class: "array", dataset: { path: pathKey(path) } });
    const [, desc] = labelOf(r, key);
    const draw = () => {
      this.dropFieldsUnder(path);
      const list = Array.isArray(this.get(path)) ? this.get(path) : [];
      if (!Array.isArray(this.get(path))) this.set(path, list);
      const label = titleOf(r, key);
      const entries = list.map((_, i) => this.arrayItem(r, path, list, i, label, draw));
      const add = h("button", { type: "button", class: "btn btn-small", onclick: () => {
        list.push(this.freshItem(r, items));
        draw();
        this.restructured();
        holder.querySelectorAll(".array-item")[list.length - 1]?.querySelector("select,input")?.focus();
      } }, `Add ${label.toLowerCase().replace(/s$/, "")}`);
      holder.replaceChildren(h("fieldset", { class: "obj" }, h("legend", {}, label),
        desc ? h("p", { class: "help" }, desc) : null,
        entries.length ? entries : h("p", { class: "help" }, "None."), add));
    };
    draw();
    return holder;
  }

  /** Item i of a list, with its Remove button. */
  arrayItem(r, path, list, i, label, redraw) {
    const block = this.node(r.items, [...path, i], `${label} ${i + 1}`);
    const remove = h("button", { type: "button", class: "btn btn-small btn-quiet", onclick: () => {
      list.splice(i, 1);
      redraw();
      this.restructured();
    } }, `Remove ${label.toLowerCase()} ${i + 1}`);
    return h("div", { class: "array-item" }, block, remove);
  }

  /** A new list item: the first variant of a union, else the item's defaults (or null). */
  freshItem(r, items) {
    if (items.oneOf && items.discriminator) return freshVariant(this.defs, items, Object.keys(items.discriminator.mapping)[0]);
    return this.defaultsOf(r.items) ?? null;
  }

  enumSet(r, items, path, key) {
    const k = pathKey(path);
    const cur = new Set(this.get(path) || []);
    const id = fieldId(path);
    const [legend, desc] = labelOf(r, key);
    const errEl = h("div", { class: "field-error", id: `${id}-err` });
    const helpId = `${id}-help`;
    const help = `${desc ? `${desc.replace(/\.?\s*$/, ".")} ` : ""}Any of ${items.enum.join(", ")}.`;
    const boxes = items.enum.map((v) => h("label", { class: "check" },
      h("input", { type: "checkbox", value: v, checked: cur.has(v), "aria-describedby": `${helpId} ${errEl.id}`, onchange: () => {
        this.set(path, boxes.map((b) => b.querySelector("input")).filter((i) => i.checked).map((i) => i.value));
        this.clearServer(k);
        this.validateField(k);
        this.updateCounts();
        this.changed();
      } }), ` ${v.replace(/_/g, " ")}`));
    const wrap = h("fieldset", { class: "field field-wide enumset", dataset: { path: k }, "aria-describedby": `${helpId} ${errEl.id}` },
      h("legend", {}, legend), h("p", { class: "help", id: helpId }, help), h("div", { class: "checks" }, boxes), errEl);
    this.fields.set(k, { wrap, input: boxes[0]?.querySelector("input"), node: r, errEl, path, kind: "enumset" });
    return wrap;
  }

  /** Typing in a scalar field: read it, recheck it (and its run-length partner), report the change. */
  scalarChanged(path, key) {
    const k = pathKey(path);
    this.clearServer(k);
    this.readInput(k);
    this.validateField(k);
    if (RUN_LENGTH_KEYS.includes(key)) RUN_LENGTH_KEYS.forEach((rk) => this.validateField(rk));
    this.updateCounts();
    this.changed();
  }

  scalarField(info, path, key, required) {
    const id = fieldId(path);
    const [label, short] = labelOf(info, key);
    const desc = helpText(info, short);
    const helpId = `${id}-help`;
    const errEl = h("div", { class: "field-error", id: `${id}-err` });
    const input = scalarInput(info, id, this.get(path), () => this.scalarChanged(path, key));
    input.setAttribute("aria-describedby", `${desc ? helpId : ""} ${errEl.id}`.trim());
    if (required) input.setAttribute("aria-required", "true");
    const unitEl = unitBadge(info);
    const cls = `field${info.type === "boolean" ? " field-check" : ""}${isLongText(info) ? " field-wide" : ""}`;
    const wrap = h("div", { class: cls, dataset: { path: pathKey(path) } },
      h("label", { for: id }, label, unitEl ? h("span", { class: "sr-only" }, ` (${unitOf(info)})`) : null,
        h("code", { class: "key", "aria-hidden": "true" }, String(key))),
      h("div", { class: "input-row" }, input, unitEl),
      desc ? h("p", { class: "help", id: helpId }, desc) : null, errEl);
    this.fields.set(pathKey(path), { wrap, input, node: info, errEl, path, kind: "scalar" });
    return wrap;
  }

  /** Any other node: its value as JSON text. */
  jsonField(r, path, key) {
    const id = fieldId(path);
    const errEl = h("div", { class: "field-error", id: `${id}-err` });
    const input = h("textarea", { id, rows: 3, class: "mono", oninput: () => {
      this.clearServer(pathKey(path));
      try {
        this.set(path, JSON.parse(input.value || "null"));
        errEl.textContent = "";
        input.removeAttribute("aria-invalid");
      } catch (e) {
        errEl.textContent = `Not valid JSON: ${e.message}`;
        input.setAttribute("aria-invalid", "true");
      }
      this.changed();
    } }, JSON.stringify(this.get(path) ?? null, null, 1));
    const [, jsonHelp] = labelOf(r, key);
    const unit = unitOf(r);
    const help = `${jsonHelp || plainDescription(r) || "A JSON value."}${unit ? ` Values in ${unit}.` : ""} Written as JSON, e.g. [[0, 0.001], [1, 0.002]].`;
    input.setAttribute("aria-describedby", `${id}-help ${errEl.id}`);
    const wrap = h("div", { class: "field field-wide", dataset: { path: pathKey(path) } },
      h("label", { for: id }, `${titleOf(r, key)} (JSON)`), input, h("p", { class: "help", id: `${id}-help` }, help), errEl);
    this.fields.set(pathKey(path), { wrap, input, node: r, errEl, path, kind: "json" });
    return wrap;
  }

  // -- values and validation ---------------------------------------------------------------

  readInput(key) {
    const f = this.fields.get(key);
    if (!f || f.kind !== "scalar" || f.node.const !== undefined) return;
    const v = readScalar(f.node, f.input);
    if (v === undefined) deleteAt(this.value, f.path);
    else this.set(f.path, v);
  }

  /** Client-side problems of a field's value (server messages aside). */
  fieldProblems(f, key) {
    const v = this.get(f.path);
    if (f.kind === "enumset") return enumSetProblems(f.node, v);
    if (f.kind !== "scalar") return [];
    const msgs = problems(f.node, v, f.input.getAttribute("aria-required") === "true");
    const runLength = RUN_LENGTH_KEYS.includes(key) && !msgs.length ? runLengthProblem(this.value) : null;
    return runLength ? [runLength] : msgs;
  }

  validateField(key) {
    const f = this.fields.get(key);
    if (!f) return [];
    let msgs = this.fieldProblems(f, key);
    const server = this.serverErrors.get(key);
    if (server) msgs = [server, ...msgs.filter((m) => !server.includes(m))];
    this.show(f, msgs, !!server);
    return msgs.map((m) => ({ path: key, msg: m }));
  }

  show(f, msgs, fromServer = false) {
    f.errEl.textContent = msgs.join("; ");
    f.errEl.classList.toggle("from-server", fromServer);
    f.wrap.classList.toggle("invalid", msgs.length > 0);
    if (f.input) {
      if (msgs.length) f.input.setAttribute("aria-invalid", "true");
      else f.input.removeAttribute("aria-invalid");
    }
  }

  /** Validate every field; returns the list of problems. */
  validateAll(showSummary = true) {
    const all = [];
    for (const key of this.fields.keys()) all.push(...this.validateField(key));
    // server errors that do not match a field
    for (const [k, msg] of this.serverErrors) if (!this.fields.has(k)) all.push({ path: k, msg });
    this.updateCounts();
    if (showSummary) this.showSummary(all);
    else if (!all.length) this.summaryEl.hidden = true;
    return all;
  }

  updateCounts() {
    updateGroupCounts(this.el);
  }

  showSummary(problems, title) {
    const hrefOf = (key) => (this.fields.has(key) ? `#${fieldId(this.fields.get(key).path)}` : null);
    showSummary(this.summaryEl, problems, title, hrefOf, (key) => this.focusField(key));
  }

  focusField(key) {
    const f = this.fields.get(key);
    if (!f) return;
    const det = f.wrap.closest("details");
    if (det) det.open = true;
    (f.input || f.wrap).focus();
    f.wrap.scrollIntoView({ block: "center" });
  }

  // -- server errors -----------------------------------------------------------------------

  /** Show the 422 items of the server at their fields; returns the items that matched none. */
  setServerErrors(items) {
    const isField = (k) => this.fields.has(k);
    const { errors, unmatched } = placeServerErrors(items, isField, (k) => isField(k) || !!blockAt(this.el, k));
    this.serverErrors = errors;
    for (const [k, msg] of this.serverErrors) this.markServer(k, msg);
    const all = this.validateAll(false);
    this.showSummary(all.length ? all : unmatched.map((u) => ({ path: u.path || "", msg: u.msg })), "The server rejected the scenario:");
    const first = [...this.serverErrors.keys()].find(isField);
    if (first) this.focusField(first);
    return unmatched;
  }

  /** Show a server message on a block (fields show theirs in validateField). */
  markServer(key, msg) {
    if (!this.fields.has(key)) markBlock(this.el, key, msg);
  }

  clearServer(key) {
    if (this.serverErrors.delete(key)) {
      const f = this.fields.get(key);
      if (f) f.errEl.classList.remove("from-server");
    }
  }
}
