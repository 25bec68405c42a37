// Client-side checks of form values against their schema node, in the server's (pydantic's) wording.

/** A bound as pydantic prints it in "(allowed: …)": 0 → "0.0". */
const pyNum = (v) => (Number.isInteger(v) ? `${v}.0` : String(v));

/** Problems of a missing or null value. */
function emptyProblems(node, v, required) {
  if (v === null) {
    if (node.nullable) return [];
    return ["Input should be a valid " + (node.type === "integer" ? "integer" : node.type === "number" ? "number" : "value")];
  }
  return required && node.default === undefined && !node.nullable ? ["Field required"] : [];
}

/** Problems of a number: type, integrality and bounds. */
function numberProblems(node, v) {
  if (typeof v !== "number") return ["Input should be a valid number, unable to parse string as a number"];
  const out = [];
  if (node.type === "integer" && !Number.isInteger(v)) out.push("Input should be a valid integer, got a number with a fractional part");
  if (node.exclusiveMinimum !== undefined && !(v > node.exclusiveMinimum)) out.push(`Input should be greater than ${node.exclusiveMinimum} (allowed: > ${pyNum(node.exclusiveMinimum)})`);
  if (node.minimum !== undefined && !(v >= node.minimum)) out.push(`Input should be greater than or equal to ${node.minimum} (allowed: ≥ ${pyNum(node.minimum)})`);
  if (node.exclusiveMaximum !== undefined && !(v < node.exclusiveMaximum)) out.push(`Input should be less than ${node.exclusiveMaximum} (allowed: < ${pyNum(node.exclusiveMaximum)})`);
  if (node.maximum !== undefined && !(v <= node.maximum)) out.push(`Input should be less than or equal to ${node.maximum} (allowed: ≤ ${pyNum(node.maximum)})`);
  return out;
}

/** Problems of a string: length, pattern and enum. */
function stringProblems(node, v) {
  const out = [];
  if (node.minLength && v.length < node.minLength) out.push(`String should have at least ${node.minLength} character${node.minLength > 1 ? "s" : ""}`);
  if (node.maxLength && v.length > node.maxLength) out.push(`String should have at most ${node.maxLength} characters`);
  if (node.pattern && !new RegExp(node.pattern).test(v)) out.push(`String should match pattern '${node.pattern}'`);
  if (node.enum && !node.enum.includes(v)) out.push(`Input should be ${node.enum.map((e) => `'${e}'`).join(", ")}`);
  return out;
}

/** Problems of one scalar value under its schema node (from scalarInfo). */
export function problems(node, v, required) {
  if (node.keyword !== undefined && v === node.keyword) return [];
  if (v === undefined || v === "" || v === null) return emptyProblems(node, v, required);
  if (node.type === "number" || node.type === "integer") return numberProblems(node, v);
  if (node.type === "string" && node.const === undefined) return stringProblems(node, v);
  return [];
}

/** Problems of a set of enum values (an array of checkboxes): its minItems. */
export function enumSetProblems(node, v) {
  const minItems = node.minItems;
  if (minItems && (!Array.isArray(v) || v.length < minItems)) return [`List should have at least ${minItems} item${minItems > 1 ? "s" : ""}`];
  return [];
}

/** The scenario keys checked together: exactly one of them gives the length of the run. */
export const RUN_LENGTH_KEYS = ["duration_s", "distance_m"];

/** The problem of a scenario that gives both or neither of duration_s and distance_m, or null. */
export function runLengthProblem(scenario) {
  const set = (x) => x !== null && x !== undefined;
  const d = set(scenario.duration_s);
  if (d !== set(scenario.distance_m)) return null;
  return d ? "Give only one of duration_s and distance_m (set the other to none)"
    : "Give one of duration_s and distance_m: the length of the run";
}
