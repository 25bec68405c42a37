// Reading the scenario's JSON schema: $ref resolution, scalar info, defaults, the variant of a
// discriminated union, and what a node is called (label, help, unit).

const SCALAR_TYPES = ["number", "integer", "string", "boolean"];

/** Deep copy of a JSON value (undefined stays undefined). */
export function clone(v) {
  return v === undefined ? undefined : JSON.parse(JSON.stringify(v));
}

/** A node with its $ref replaced by the definition it names (the node's own keys win). */
export function resolve(defs, node) {
  if (!node) return {};
  if (!node.$ref) return node;
  const target = defs[node.$ref.split("/").pop()] || {};
  const { $ref, ...rest } = node;
  return { ...target, ...rest, description: rest.description || target.description };
}

/** A member of an `anyOf` that is one word instead of a value (solver.dt: "auto"), or undefined. */
const keywordOf = (x) => (x.type === "string" && typeof x.const === "string" ? x.const : undefined);

/**
 * Scalar info of an `anyOf` node: nullable, a keyword the field may hold instead of a value
 * (`{const: "auto"}`: the empty input), and the one remaining member merged in.
 */
function anyOfInfo(defs, node) {
  const nonNull = node.anyOf.filter((x) => x.type !== "null");
  const nullable = nonNull.length < node.anyOf.length;
  const keywords = nonNull.map(keywordOf).filter((k) => k !== undefined);
  const values = nonNull.filter((x) => keywordOf(x) === undefined);
  if (values.length !== 1 || keywords.length > 1) return { ...node, nullable, isScalar: false };
  const inner = resolve(defs, values[0]);
  return {
    ...inner, description: node.description, unit: node.unit ?? inner.unit, title: node.title,
    default: node.default, nullable, keyword: keywords[0], isScalar: SCALAR_TYPES.includes(inner.type),
  };
}

/** Numeric/nullable info of a node: {type, nullable, isScalar, bounds, enum, const, …}. */
export function scalarInfo(defs, node) {
  node = resolve(defs, node);
  if (node.anyOf) return anyOfInfo(defs, node);
  return { ...node, nullable: false, isScalar: SCALAR_TYPES.includes(node.type) || node.const !== undefined };
}

/** The value a fresh node starts with: its default, const, the defaults of its properties, null or []. */
export function defaultsOf(defs, node) {
  const r = resolve(defs, node);
  if (r.default !== undefined) return clone(r.default);
  if (r.const !== undefined) return r.const;
  if (r.type === "object" || r.properties) {
    const o = {};
    for (const [k, sub] of Object.entries(r.properties || {})) {
      const d = defaultsOf(defs, sub);
      if (d !== undefined) o[k] = d;
    }
    return o;
  }
  if (scalarInfo(defs, node).nullable) return null;
  if (r.type === "array") return [];
  return undefined;
}

/** Defaults of the variant `kind` of a discriminated union, with its discriminator set. */
export function freshVariant(defs, union, kind) {
  const fresh = defaultsOf(defs, { $ref: union.discriminator.mapping[kind] });
  fresh[union.discriminator.propertyName] = kind;
  return fresh;
}

/** The variant a value of a discriminated union is: {prop, kind, schema} (schema null if unknown). */
export function variantOf(defs, union, v) {
  const prop = union.discriminator.propertyName;
  const kind = v && v[prop];
  const ref = union.discriminator.mapping[kind];
  return { prop, kind, schema: ref ? resolve(defs, { $ref: ref }) : null };
}

// -- names, descriptions, units -----------------------------------------------------------------

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

/** Readable name of a property: speed_kmh → "Speed", rail_head_radius → "Rail head radius". */
export function humanKey(key) {
  const k = String(key ?? "").replace(/_(kmh|m|s|hz|mb|kn)$/i, "");
  const t = k.replace(/_/g, " ");
  return t.charAt(0).toUpperCase() + t.slice(1);
}

/** [label, help] of a node: a short description is the label, a long one the help text. */
export function labelOf(node, key) {
  const text = plainDescription(node);
  const first = String(text || "").split("\n")[0].trim();
  if (first && first.length <= 48 && !/[.:;]\s/.test(first)) return [first, null];
  return [humanKey(key ?? node?.title), first || null];
}

/** The label of a node alone. */
export function titleOf(node, key) {
  return labelOf(node, key)[0];
}

/** A number as the help text writes it: 8e10 rather than 80000000000. */
function num(v) {
  if (typeof v !== "number") return String(v);
  const a = Math.abs(v);
  return a !== 0 && (a >= 1e6 || a < 1e-3) ? v.toExponential().replace("e+", "e") : String(v);
}

/** The allowed values of a scalar node in words: "0 < value ≤ 200 km/h", "one of a, b". */
export function rangeText(info) {
  const unit = unitOf(info);
  const u = unit && unit !== "-" ? ` ${unit}` : "";
  if (Array.isArray(info.enum)) return `one of ${info.enum.join(", ")}`;
  if (info.type === "string") return info.maxLength ? `text of up to ${info.maxLength} characters` : "text";
  if (info.type === "boolean") return "on or off";
  if (info.type !== "number" && info.type !== "integer") return "";
  const lo = info.exclusiveMinimum ?? info.minimum;
  const hi = info.exclusiveMaximum ?? info.maximum;
  const loOp = info.exclusiveMinimum !== undefined ? "<" : "≤";
  const hiOp = info.exclusiveMaximum !== undefined ? "<" : "≤";
  const what = info.type === "integer" ? "a whole number" : "value";
  if (lo !== undefined && hi !== undefined) return `${num(lo)} ${loOp} ${what} ${hiOp} ${num(hi)}${u}`;
  if (lo !== undefined) return `${what} ${loOp === "<" ? ">" : "≥"} ${num(lo)}${u}`;
  if (hi !== undefined) return `${what} ${hiOp} ${num(hi)}${u}`;
  return unit ? `in ${unit === "-" ? "– (dimensionless)" : unit}` : "";
}

/** The default of a node in words, or "". */
function defaultText(info) {
  if (info.default === undefined) return "";
  if (info.default === null) return "default: none";
  if (typeof info.default === "boolean") return `default: ${info.default ? "on" : "off"}`;
  if (typeof info.default === "object" || info.default === "") return "";
  if (typeof info.default === "string") return `default “${info.default}”`;
  const unit = unitOf(info);
  return `default ${num(info.default)}${unit && unit !== "-" && typeof info.default === "number" ? ` ${unit}` : ""}`;
}

/**
 * The complete help of a scalar field: its description (when the label is not already it), the
 * allowed values with the unit, the default, and whether it may be left empty.
 */
export function helpText(info, desc) {
  const empty = info.keyword !== undefined ? `may be left empty (${info.keyword})` : info.nullable ? "may be left empty (none)" : "";
  const parts = [rangeText(info), defaultText(info), empty].filter(Boolean);
  const tail = parts.length ? `${parts.join("; ")}.` : "";
  const head = desc ? `${desc.replace(/\.?\s*$/, ".")}` : "";
  return [head, tail].filter(Boolean).join(" ") || null;
}
