// A form generated from the scenario's JSON schema (GET /api/v1/schemas/scenario): groups,
// units from the schema's "unit" of each quantity, bounds checked as you type with the server's wording,
// and the server's 422 messages shown at the field they name.

import { h, prettyUnit } from "./dom.js";

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

/** Unit of a schema node: the schema's own `unit` (pydantic `quantity` fields), or null. */
export function unitOf(node) {
  return node?.unit ?? null;
}

/** Description of a schema node without the " (unit)" its schema closes it with. */
export function plainDescription(node) {
  const s = String(node?.description || "").trim();
  const unit = unitOf(node);
  const tail = unit ? ` (${unit})` : null;
  return tail && s.endsWith(tail) ? s.slice(0, -tail.length).trim() : s;
}

const pyNum = (v) => (Number.isInteger(v) ? `${v}.0` : String(v));

/** Number as typed text: 8e10 rather than 80000000000. */
export function numText(v) {
  if (v === null || v === undefined) return "";
  if (typeof v !== "number") return String(v);
  const a = Math.abs(v);
  if (a !== 0 && (a >= 1e6 || a < 1e-4)) return v.toExponential().replace("e+", "e").replace(/\.?0+e/, "e");
  return String(v);
}

function pathKey(path) {
  return path.join(".");
}
function fieldId(path) {
  return `f-${path.join("-").replace(/[^A-Za-z0-9_-]/g, "_")}`;
}
function clone(v) {
  return v === undefined ? undefined : JSON.parse(JSON.stringify(v));
}

/** Readable name of a property: speed_kmh → "Speed", rail_head_radius → "Rail head radius". */
export function humanKey(key) {
  const k = String(key ?? "").replace(/_(kmh|m|s|hz|mb|kn)$/i, "");
  const t = k.replace(/_/g, " ");
  return t.charAt(0).toUpperCase() + t.slice(1);
}

/** [label, help] of a node: a short description is the label, a long one the help text. */
function labelOf(node, key) {
  const text = plainDescription(node);
  const first = String(text || "").split("\n")[0].trim();
  if (first && first.length <= 48 && !/[.:;]\s/.test(first)) return [first, null];
  return [humanKey(key ?? node?.title), first || null];
}

function titleOf(node, key) {
  return labelOf(node, key)[0];
}

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
    this.fields = new Map(); // path → {wrap, input, node, errEl, group}
    this.serverErrors = new Map();
    this.el = h("div", { class: "schema-form" });
    this.render();
  }

  resolve(node) {
    if (!node) return {};
    if (node.$ref) {
      const name = node.$ref.split("/").pop();
      const target = this.defs[name] || {};
      const { $ref, ...rest } = node;
      return { ...target, ...rest, description: rest.description || target.description };
    }
    return node;
  }

  /** Numeric/nullable info of a node: {type, nullable, bounds, enum, const}. */
  scalarInfo(node) {
    node = this.resolve(node);
    if (node.anyOf) {
      const nonNull = node.anyOf.filter((x) => x.type !== "null");
      const nullable = nonNull.length < node.anyOf.length;
      if (nonNull.length === 1) {
        const inner = this.resolve(nonNull[0]);
        return { ...inner, description: node.description, unit: node.unit ?? inner.unit, title: node.title, default: node.default, nullable, isScalar: ["number", "integer", "string", "boolean"].includes(inner.type) };
      }
      return { ...node, nullable, isScalar: false };
    }
    return { ...node, nullable: false, isScalar: ["number", "integer", "string", "boolean"].includes(node.type) || node.const !== undefined };
  }

  get(path, root = this.value) {
    let v = root;
    for (const p of path) {
      if (v === null || v === undefined) return undefined;
      v = v[p];
    }
    return v;
  }

  set(path, val) {
    let v = this.value;
    for (let i = 0; i < path.length - 1; i++) {
      const p = path[i];
      if (v[p] === null || v[p] === undefined || typeof v[p] !== "object") v[p] = typeof path[i + 1] === "number" ? [] : {};
      v = v[p];
    }
    v[path[path.length - 1]] = val;
  }

  setValue(value) {
    this.value = clone(value) || {};
    this.serverErrors.clear();
    this.render();
  }

  changed() {
    this.opts.onChange?.(this.value);
  }

  // -- rendering ---------------------------------------------------------------------------

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

  groupSection(g, keys, open) {
    const body = h("div", { class: "group-body" });
    const count = h("span", { class: "group-errors", "aria-live": "polite" });
    const det = h("details", { class: "group", dataset: { group: g.id }, open },
      h("summary", {}, h("span", { class: "group-title" }, g.label), count), body);
    let grid = null;
    for (const k of keys) {
      const el = this.node(this.schema.properties[k], [k], k, (this.schema.required || []).includes(k));
      if (el.classList.contains("field") && !el.classList.contains("field-wide")) {
        if (!grid) {
          grid = h("div", { class: "fields" });
          body.append(grid);
        }
        grid.append(el);
      } else {
        grid = null;
        body.append(el);
      }
    }
    return det;
  }

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
    for (const [k, sub] of Object.entries(r.properties || {})) {
      grid.append(this.node(sub, [...path, k], k, (r.required || []).includes(k)));
    }
    fs.append(grid);
    return fs;
  }

  variantOf(r, v) {
    const prop = r.discriminator.propertyName;
    const kind = v && v[prop];
    const ref = r.discriminator.mapping[kind];
    return { prop, kind, schema: ref ? this.resolve({ $ref: ref }) : null };
  }

  defaultsOf(node) {
    const r = this.resolve(node);
    if (r.default !== undefined) return clone(r.default);
    if (r.const !== undefined) return r.const;
    if (r.type === "object" || r.properties) {
      const o = {};
      for (const [k, sub] of Object.entries(r.properties || {})) {
        const d = this.defaultsOf(sub);
        if (d !== undefined) o[k] = d;
      }
      return o;
    }
    const info = this.scalarInfo(node);
    if (info.nullable) return null;
    if (r.type === "array") return [];
    return undefined;
  }

  variantBlock(r, path, key) {
    const holder = h("div", { class: "variant", dataset: { path: pathKey(path) } });
    const draw = () => {
      const v = this.get(path) || {};
      const { prop, kind, schema } = this.variantOf(r, v);
      const id = fieldId([...path, prop]);
      const sel = h("select", { id, onchange: () => {
        const ref = r.discriminator.mapping[sel.value];
        const fresh = this.defaultsOf({ $ref: ref });
        fresh[prop] = sel.value;
        this.set(path, fresh);
        draw();
        this.validateAll(false);
        this.changed();
      } }, Object.keys(r.discriminator.mapping).map((k) => h("option", { value: k, selected: k === kind }, k)));
      const desc = plainDescription(schema);
      const fs = h("fieldset", { class: "obj" }, h("legend", {}, titleOf(r, key)),
        h("div", { class: "field field-wide" }, h("label", { for: id }, "Kind"), sel,
          desc ? h("p", { class: "help" }, desc.split("\n")[0]) : null));
      const grid = h("div", { class: "fields" });
      if (schema) {
        for (const [k, sub] of Object.entries(schema.properties || {})) {
          if (k === prop) continue;
          grid.append(this.node(sub, [...path, k], k, (schema.required || []).includes(k)));
        }
      }
      fs.append(grid);
      for (const k of [...this.fields.keys()]) {
        if (k.startsWith(`${pathKey(path)}.`) && !fs.contains(this.fields.get(k).wrap)) {
          const f = this.fields.get(k);
          if (!f.wrap.isConnected || holder.contains(f.wrap)) this.fields.delete(k);
        }
      }
      holder.replaceChildren(fs);
    };
    draw();
    return holder;
  }

  arrayBlock(r, path, key) {
    const items = this.resolve(r.items || {});
    const enumItems = items.enum && items.type === "string";
    if (enumItems) return this.enumSet(r, items, path, key);
    const holder = h("div", { class: "array", dataset: { path: pathKey(path) } });
    const [, desc] = labelOf(r, key);
    const draw = () => {
      for (const k of [...this.fields.keys()]) if (k.startsWith(`${pathKey(path)}.`)) this.fields.delete(k);
      const list = Array.isArray(this.get(path)) ? this.get(path) : [];
      if (!Array.isArray(this.get(path))) this.set(path, list);
      const label = titleOf(r, key);
      const entries = list.map((_, i) => {
        const itemNode = r.items;
        const block = this.node(itemNode, [...path, i], `${label} ${i + 1}`);
        const remove = h("button", { type: "button", class: "btn btn-small btn-quiet", onclick: () => {
          list.splice(i, 1);
          draw();
          this.validateAll(false);
          this.changed();
        } }, `Remove ${label.toLowerCase()} ${i + 1}`);
        return h("div", { class: "array-item" }, block, remove);
      });
      const add = h("button", { type: "button", class: "btn btn-small", onclick: () => {
        let fresh;
        if (items.oneOf && items.discriminator) {
          const first = Object.keys(items.discriminator.mapping)[0];
          fresh = this.defaultsOf({ $ref: items.discriminator.mapping[first] });
          fresh[items.discriminator.propertyName] = first;
        } else fresh = this.defaultsOf(r.items) ?? null;
        list.push(fresh);
        draw();
        this.validateAll(false);
        this.changed();
        holder.querySelectorAll(".array-item")[list.length - 1]?.querySelector("select,input")?.focus();
      } }, `Add ${label.toLowerCase().replace(/s$/, "")}`);
      holder.replaceChildren(h("fieldset", { class: "obj" }, h("legend", {}, label),
        desc ? h("p", { class: "help" }, desc) : null,
        entries.length ? entries : h("p", { class: "help" }, "None."), add));
    };
    draw();
    return holder;
  }

  enumSet(r, items, path, key) {
    const cur = new Set(this.get(path) || []);
    const id = fieldId(path);
    const [legend, desc] = labelOf(r, key);
    const errEl = h("div", { class: "field-error", id: `${id}-err` });
    const boxes = items.enum.map((v) => h("label", { class: "check" },
      h("input", { type: "checkbox", value: v, checked: cur.has(v), onchange: () => {
        const vals = boxes.map((b) => b.querySelector("input")).filter((i) => i.checked).map((i) => i.value);
        this.set(path, vals);
        this.clearServer(pathKey(path));
        this.validateField(pathKey(path));
        this.updateCounts();
        this.changed();
      } }), ` ${v.replace(/_/g, " ")}`));
    const wrap = h("fieldset", { class: "field field-wide enumset", dataset: { path: pathKey(path) }, "aria-describedby": `${id}-err` },
      h("legend", {}, legend), desc ? h("p", { class: "help" }, desc) : null, h("div", { class: "checks" }, boxes), errEl);
    this.fields.set(pathKey(path), { wrap, input: boxes[0]?.querySelector("input"), node: r, errEl, path, kind: "enumset" });
    return wrap;
  }

  scalarField(info, path, key, required) {
    const id = fieldId(path);
    const unit = unitOf(info);
    const [label, desc] = labelOf(info, key);
    const v = this.get(path);
    const helpId = `${id}-help`;
    const errId = `${id}-err`;
    const errEl = h("div", { class: "field-error", id: errId });
    let input;
    const onInput = () => {
      this.clearServer(pathKey(path));
      this.readInput(pathKey(path));
      this.validateField(pathKey(path));
      if (key === "duration_s" || key === "distance_m") {
        this.validateField("duration_s");
        this.validateField("distance_m");
      }
      this.updateCounts();
      this.changed();
    };
    if (info.const !== undefined) {
      input = h("input", { id, type: "text", value: String(info.const), readonly: true });
    } else if (info.type === "boolean") {
      input = h("input", { id, type: "checkbox", checked: !!v, onchange: onInput });
    } else if (info.enum) {
      input = h("select", { id, onchange: onInput },
        info.nullable ? h("option", { value: "", selected: v === null || v === undefined }, "(none)") : null,
        info.enum.map((e) => h("option", { value: e, selected: e === v }, String(e))));
    } else if (info.type === "string" && (info.maxLength || 0) > 200) {
      input = h("textarea", { id, rows: 2, oninput: onInput }, v ?? "");
    } else {
      const numeric = info.type === "number" || info.type === "integer";
      input = h("input", {
        id, type: "text", value: numeric ? numText(v) : v ?? "", oninput: onInput,
        inputmode: numeric ? (info.type === "integer" ? "numeric" : "decimal") : null,
        autocomplete: "off", spellcheck: numeric ? "false" : null,
        placeholder: info.nullable ? "none" : null,
      });
    }
    input.setAttribute("aria-describedby", `${desc ? helpId : ""} ${errId}`.trim());
    if (required) input.setAttribute("aria-required", "true");
    const unitEl = unit && (info.type === "number" || info.type === "integer")
      ? h("span", { class: "unit", title: unit === "-" ? "dimensionless" : `unit: ${unit}` }, prettyUnit(unit)) : null;
    const wrap = h("div", { class: `field${info.type === "boolean" ? " field-check" : ""}${(info.maxLength || 0) > 200 ? " field-wide" : ""}`, dataset: { path: pathKey(path) } },
      h("label", { for: id }, label, unitEl ? h("span", { class: "sr-only" }, ` (${unit})`) : null,
        h("code", { class: "key", "aria-hidden": "true" }, String(key))),
      h("div", { class: "input-row" }, input, unitEl),
      desc ? h("p", { class: "help", id: helpId }, desc) : null, errEl);
    this.fields.set(pathKey(path), { wrap, input, node: info, errEl, path, kind: "scalar" });
    return wrap;
  }

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
    const wrap = h("div", { class: "field field-wide", dataset: { path: pathKey(path) } },
      h("label", { for: id }, `${titleOf(r, key)} (JSON)`), input, errEl);
    this.fields.set(pathKey(path), { wrap, input, node: r, errEl, path, kind: "json" });
    return wrap;
  }

  // -- values and validation ---------------------------------------------------------------

  readInput(key) {
    const f = this.fields.get(key);
    if (!f || f.kind !== "scalar") return;
    const { input, node, path } = f;
    if (node.const !== undefined) return;
    let v;
    if (node.type === "boolean") v = input.checked;
    else if (node.enum) v = input.value === "" && node.nullable ? null : input.value;
    else if (node.type === "number" || node.type === "integer") {
      const t = input.value.trim();
      if (t === "") v = node.nullable ? null : undefined;
      else {
        const n = Number(t.replace(/\s/g, "").replace(/,/g, "."));
        v = Number.isFinite(n) ? n : t; // keep the text: the validator reports it
      }
    } else {
      v = input.value;
      if (v === "" && node.nullable) v = null;
    }
    if (v === undefined) this.deleteAt(path);
    else this.set(path, v);
  }

  deleteAt(path) {
    const parent = this.get(path.slice(0, -1));
    if (parent && typeof parent === "object") delete parent[path[path.length - 1]];
  }

  /** Problems of one value under its schema node (pydantic's wording). */
  problems(node, v, required, key) {
    if (v === undefined || v === "") return required && node.default === undefined && !node.nullable ? ["Field required"] : [];
    if (v === null) return node.nullable ? [] : ["Input should be a valid " + (node.type === "integer" ? "integer" : node.type === "number" ? "number" : "value")];
    const out = [];
    if (node.type === "number" || node.type === "integer") {
      if (typeof v !== "number") return ["Input should be a valid number, unable to parse string as a number"];
      if (node.type === "integer" && !Number.isInteger(v)) out.push("Input should be a valid integer, got a number with a fractional part");
      if (node.exclusiveMinimum !== undefined && !(v > node.exclusiveMinimum)) out.push(`Input should be greater than ${node.exclusiveMinimum} (allowed: > ${pyNum(node.exclusiveMinimum)})`);
      if (node.minimum !== undefined && !(v >= node.minimum)) out.push(`Input should be greater than or equal to ${node.minimum} (allowed: ≥ ${pyNum(node.minimum)})`);
      if (node.exclusiveMaximum !== undefined && !(v < node.exclusiveMaximum)) out.push(`Input should be less than ${node.exclusiveMaximum} (allowed: < ${pyNum(node.exclusiveMaximum)})`);
      if (node.maximum !== undefined && !(v <= node.maximum)) out.push(`Input should be less than or equal to ${node.maximum} (allowed: ≤ ${pyNum(node.maximum)})`);
    } else if (node.type === "string" && node.const === undefined) {
      if (node.minLength && v.length < node.minLength) out.push(`String should have at least ${node.minLength} character${node.minLength > 1 ? "s" : ""}`);
      if (node.maxLength && v.length > node.maxLength) out.push(`String should have at most ${node.maxLength} characters`);
      if (node.pattern && !new RegExp(node.pattern).test(v)) out.push(`String should match pattern '${node.pattern}'`);
      if (node.enum && !node.enum.includes(v)) out.push(`Input should be ${node.enum.map((e) => `'${e}'`).join(", ")}`);
    }
    void key;
    return out;
  }

  validateField(key) {
    const f = this.fields.get(key);
    if (!f) return [];
    let msgs = [];
    const v = this.get(f.path);
    if (f.kind === "scalar") {
      const required = f.input.getAttribute("aria-required") === "true";
      msgs = this.problems(f.node, v, required, key);
      if ((key === "duration_s" || key === "distance_m") && !msgs.length) {
        const d = this.value.duration_s;
        const m = this.value.distance_m;
        const set = (x) => x !== null && x !== undefined;
        if (set(d) === set(m)) {
          msgs.push(set(d) ? "Give only one of duration_s and distance_m (set the other to none)"
            : "Give one of duration_s and distance_m: the length of the run");
        }
      }
    } else if (f.kind === "enumset") {
      const minItems = f.node.minItems;
      if (minItems && (!Array.isArray(v) || v.length < minItems)) msgs.push(`List should have at least ${minItems} item${minItems > 1 ? "s" : ""}`);
    }
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
    for (const det of this.el.querySelectorAll("details[data-group]")) {
      const n = det.querySelectorAll(".field.invalid, .enumset.invalid").length;
      const c = det.querySelector(".group-errors");
      c.textContent = n ? `${n} problem${n > 1 ? "s" : ""}` : "";
    }
  }

  showSummary(problems, title) {
    if (!problems.length) {
      this.summaryEl.hidden = true;
      return;
    }
    this.summaryEl.hidden = false;
    this.summaryEl.replaceChildren(
      h("strong", {}, title || `${problems.length} problem${problems.length > 1 ? "s" : ""} to fix before submitting:`),
      h("ul", {}, problems.slice(0, 20).map((p) => h("li", {},
        this.fields.has(p.path) ? h("a", { href: `#${fieldId(this.fields.get(p.path).path)}`, onclick: (e) => {
          e.preventDefault();
          this.focusField(p.path);
        } }, p.path) : h("code", {}, p.path || "scenario"), `: ${p.msg}`))));
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
    this.serverErrors.clear();
    const unmatched = [];
    for (const it of items || []) {
      let loc = (it.loc || []).map(String);
      while (loc.length && ["body", "scenario"].includes(loc[0])) loc = loc.slice(1);
      const msg = String(it.msg || "");
      let key = loc.join(".");
      // the nearest rendered field or block
      while (key && !this.fields.has(key) && !this.el.querySelector(`[data-path="${cssEsc(key)}"]`)) {
        key = key.includes(".") ? key.slice(0, key.lastIndexOf(".")) : "";
      }
      if (!key) {
        unmatched.push({ ...it, msg });
        continue;
      }
      const prev = this.serverErrors.get(key);
      this.serverErrors.set(key, prev ? `${prev}; ${msg}` : msg);
      if (!this.fields.has(key)) unmatched.push({ ...it, msg, path: key });
    }
    for (const [k, msg] of this.serverErrors) this.markServer(k, msg);
    const all = this.validateAll(false);
    this.showSummary(all.length ? all : unmatched.map((u) => ({ path: u.path || "", msg: u.msg })), "The server rejected the scenario:");
    const first = [...this.serverErrors.keys()].find((k) => this.fields.has(k));
    if (first) this.focusField(first);
    return unmatched;
  }

  markServer(key, msg) {
    const f = this.fields.get(key);
    if (f) return;
    const block = this.el.querySelector(`[data-path="${cssEsc(key)}"]`);
    if (!block) return;
    let note = block.querySelector(":scope > .block-error");
    if (!note) {
      note = h("div", { class: "field-error block-error from-server" });
      block.prepend(note);
    }
    note.textContent = msg;
    const det = block.closest("details");
    if (det) det.open = true;
  }

  clearServer(key) {
    if (this.serverErrors.delete(key)) {
      const f = this.fields.get(key);
      if (f) f.errEl.classList.remove("from-server");
    }
  }
}


function cssEsc(s) {
  return window.CSS?.escape ? CSS.escape(s) : s.replace(/"/g, '\\"');
}
