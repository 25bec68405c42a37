// The input element of one scalar schema node (text, number, checkbox, select, textarea, const),
// its unit badge, and the value read back from it.

import { h, prettyUnit } from "./dom.js";
import { unitOf } from "./schema.js";

/** Number as typed text: 8e10 rather than 80000000000. */
export function numText(v) {
  if (v === null || v === undefined) return "";
  if (typeof v !== "number") return String(v);
  const a = Math.abs(v);
  if (a !== 0 && (a >= 1e6 || a < 1e-4)) return v.toExponential().replace("e+", "e").replace(/\.?0+e/, "e");
  return String(v);
}

const isNumeric = (info) => info.type === "number" || info.type === "integer";

/** Whether a string node is long text, shown as a wide textarea. */
export const isLongText = (info) => (info.maxLength || 0) > 200;

/** A select of the node's enum values, with "(none)" first when the node is nullable. */
function enumSelect(info, id, v, onInput) {
  return h("select", { id, onchange: onInput },
    info.nullable ? h("option", { value: "", selected: v === null || v === undefined }, "(none)") : null,
    info.enum.map((e) => h("option", { value: e, selected: e === v }, String(e))));
}

/** A text input for a number or a short string (its keyword, e.g. auto, shown as the empty input). */
function textInput(info, id, v, onInput) {
  const numeric = isNumeric(info);
  const shown = info.keyword !== undefined && v === info.keyword ? "" : v;
  return h("input", {
    id, type: "text", value: numeric ? numText(shown) : shown ?? "", oninput: onInput,
    inputmode: numeric ? (info.type === "integer" ? "numeric" : "decimal") : null,
    autocomplete: "off", spellcheck: numeric ? "false" : null,
    placeholder: info.keyword ?? (info.nullable ? "none" : null),
  });
}

/** The input element for a scalar node (from scalarInfo) holding value `v`. */
export function scalarInput(info, id, v, onInput) {
  if (info.const !== undefined) return h("input", { id, type: "text", value: String(info.const), readonly: true });
  if (info.type === "boolean") return h("input", { id, type: "checkbox", checked: !!v, onchange: onInput });
  if (info.enum) return enumSelect(info, id, v, onInput);
  if (info.type === "string" && isLongText(info)) return h("textarea", { id, rows: 2, oninput: onInput }, v ?? "");
  return textInput(info, id, v, onInput);
}

/** The unit shown after a numeric input, or null. */
export function unitBadge(info) {
  const unit = unitOf(info);
  if (!unit || !isNumeric(info)) return null;
  return h("span", { class: "unit", title: unit === "-" ? "dimensionless" : `unit: ${unit}` }, prettyUnit(unit));
}

/**
 * Number typed in a text input: the node's keyword when empty or typed, else null/undefined when
 * empty, the text itself when it does not parse.
 */
function readNumber(node, text) {
  const t = text.trim();
  if (node.keyword !== undefined && (t === "" || t.toLowerCase() === node.keyword)) return node.keyword;
  if (t === "") return node.nullable ? null : undefined;
  const n = Number(t.replace(/\s/g, "").replace(/,/g, "."));
  return Number.isFinite(n) ? n : t; // keep the text: the validator reports it
}

/** The value of a scalar input (undefined: remove the key). Not called for const nodes. */
export function readScalar(node, input) {
  if (node.type === "boolean") return input.checked;
  if (node.enum) return input.value === "" && node.nullable ? null : input.value;
  if (isNumeric(node)) return readNumber(node, input.value);
  return input.value === "" && node.nullable ? null : input.value;
}
