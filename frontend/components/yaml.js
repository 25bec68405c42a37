// A small YAML reader and writer for scenario files (the subset flexride scenarios use:
// block mappings and sequences, flow [..] and {..}, plain / quoted scalars, | and > blocks,
// comments). JSON is YAML too and is read by JSON.parse first.

export class YamlError extends Error {
  constructor(message, line) {
    super(line ? `line ${line}: ${message}` : message);
    this.line = line;
  }
}

/** Parse YAML or JSON text into a value. */
export function parseYamlOrJson(text) {
  const t = String(text ?? "").replace(/^\uFEFF/, "");
  if (/^\s*[[{]/.test(t)) {
    try {
      return JSON.parse(t);
    } catch (e) {
      // flow-style YAML, or JSON with a mistake: try YAML, report the JSON error if both fail
      try {
        return parseYaml(t);
      } catch {
        throw new YamlError(`not valid JSON: ${e.message}`);
      }
    }
  }
  return parseYaml(t);
}

function stripComment(line) {
  let q = null;
  for (let i = 0; i < line.length; i++) {
    const c = line[i];
    if (q) {
      if (c === q && !(q === '"' && line[i - 1] === "\\")) q = null;
    } else if (c === '"' || c === "'") q = c;
    else if (c === "#" && (i === 0 || /\s/.test(line[i - 1]))) return line.slice(0, i);
  }
  return line;
}

export function scalar(raw, lineNo) {
  const s = raw.trim();
  if (s === "" || s === "~" || s === "null" || s === "Null" || s === "NULL") return null;
  if (/^(true|True|TRUE)$/.test(s)) return true;
  if (/^(false|False|FALSE)$/.test(s)) return false;
  if (/^[-+]?(\d[\d_]*)?(\.\d*)?([eE][-+]?\d+)?$/.test(s) && /\d/.test(s)) return Number(s.replace(/_/g, ""));
  if (/^[-+]?\.(inf|Inf|INF)$/.test(s)) return s.startsWith("-") ? -Infinity : Infinity;
  if (/^\.(nan|NaN|NAN)$/.test(s)) return NaN;
  if (s.startsWith('"')) {
    if (!s.endsWith('"') || s.length < 2) throw new YamlError("unterminated double-quoted string", lineNo);
    try {
      return JSON.parse(s);
    } catch {
      throw new YamlError(`bad string ${s}`, lineNo);
    }
  }
  if (s.startsWith("'")) {
    if (!s.endsWith("'") || s.length < 2) throw new YamlError("unterminated single-quoted string", lineNo);
    return s.slice(1, -1).replace(/''/g, "'");
  }
  if (s.startsWith("[") || s.startsWith("{")) return flow(s, lineNo);
  return s;
}

// Flow collections: [a, b, {c: 1}] with plain scalars.
function flow(s, lineNo) {
  let i = 0;
  const ws = () => { while (i < s.length && /\s/.test(s[i])) i++; };
  function value() {
    ws();
    if (s[i] === "[") {
      i++;
      const out = [];
      ws();
      if (s[i] === "]") { i++; return out; }
      for (;;) {
        out.push(value());
        ws();
        if (s[i] === ",") { i++; ws(); if (s[i] === "]") { i++; return out; } continue; }
        if (s[i] === "]") { i++; return out; }
        throw new YamlError(`expected , or ] in ${s}`, lineNo);
      }
    }
    if (s[i] === "{") {
      i++;
      const out = {};
      ws();
      if (s[i] === "}") { i++; return out; }
      for (;;) {
        ws();
        const k = token(":");
        if (s[i] !== ":") throw new YamlError(`expected : in ${s}`, lineNo);
        i++;
        out[String(scalar(k, lineNo))] = value();
        ws();
        if (s[i] === ",") { i++; continue; }
        if (s[i] === "}") { i++; return out; }
        throw new YamlError(`expected , or } in ${s}`, lineNo);
      }
    }
    return scalar(token(), lineNo);
  }
  function token(stop = "") {
    ws();
    const start = i;
    if (s[i] === '"' || s[i] === "'") {
      const q = s[i++];
      while (i < s.length && !(s[i] === q && s[i - 1] !== "\\")) i++;
      i++;
      return s.slice(start, i);
    }
    while (i < s.length && !",]}".includes(s[i]) && !(stop && s[i] === stop)) i++;
    return s.slice(start, i);
  }
  const v = value();
  ws();
  if (i !== s.length) throw new YamlError(`unexpected text after ${s.slice(0, i)}`, lineNo);
  return v;
}

/** Parse block YAML. */
export function parseYaml(text) {
  const lines = [];
  String(text).split(/\r?\n/).forEach((raw, n) => {
    if (/^\s*---\s*$/.test(raw) || /^\s*\.\.\.\s*$/.test(raw)) return;
    if (raw.includes("\t") && /^\s*\t/.test(raw)) throw new YamlError("tabs are not allowed for indentation", n + 1);
    lines.push({ raw, n: n + 1 });
  });
  let pos = 0;

  const content = (l) => stripComment(l.raw).replace(/\s+$/, "");
  const indentOf = (l) => l.raw.match(/^ */)[0].length;
  function skipBlank() {
    while (pos < lines.length && content(lines[pos]).trim() === "") pos++;
  }

  function blockScalar(style, parentIndent) {
    const out = [];
    let ind = null;
    while (pos < lines.length) {
      const l = lines[pos];
      if (l.raw.trim() === "") { out.push(""); pos++; continue; }
      const i = indentOf(l);
      if (i <= parentIndent) break;
      if (ind === null) ind = i;
      out.push(l.raw.slice(ind));
      pos++;
    }
    while (out.length && out[out.length - 1] === "") out.pop();
    return style.startsWith("|") ? `${out.join("\n")}\n` : `${out.join(" ").replace(/ {2,}/g, " ")}\n`;
  }

  function parseBlock(indent) {
    skipBlank();
    if (pos >= lines.length) return null;
    const first = lines[pos];
    const c = content(first).trim();
    if (c.startsWith("- ") || c === "-") return parseSeq(indentOf(first));
    return parseMap(indentOf(first));
  }

  function valueAfter(rest, ownIndent, lineNo) {
    const r = rest.trim();
    if (r === "") {
      skipBlank();
      if (pos < lines.length && indentOf(lines[pos]) > ownIndent) return parseBlock(indentOf(lines[pos]));
      if (pos < lines.length && indentOf(lines[pos]) === ownIndent && /^-( |$)/.test(content(lines[pos]).trim())) {
        return parseSeq(ownIndent); // "key:\n- a\n- b" (sequence at the same indent)
      }
      return null;
    }
    if (/^[|>][-+]?$/.test(r)) return blockScalar(r, ownIndent);
    return scalar(r, lineNo);
  }

  function splitKey(s, lineNo) {
    let q = null;
    for (let i = 0; i < s.length; i++) {
      const ch = s[i];
      if (q) { if (ch === q) q = null; continue; }
      if (ch === '"' || ch === "'") { q = ch; continue; }
      if (ch === ":" && (i + 1 === s.length || s[i + 1] === " ")) {
        const k = s.slice(0, i).trim();
        return [String(scalar(k, lineNo)), s.slice(i + 1)];
      }
    }
    return null;
  }

  function parseMap(indent) {
    const out = {};
    while (pos < lines.length) {
      skipBlank();
      if (pos >= lines.length) break;
      const l = lines[pos];
      const i = indentOf(l);
      if (i < indent) break;
      if (i > indent) throw new YamlError("unexpected indentation", l.n);
      const c = content(l).trim();
      if (c.startsWith("- ")) break;
      const kv = splitKey(c, l.n);
      if (!kv) throw new YamlError(`expected "key: value", got "${c}"`, l.n);
      pos++;
      if (Object.prototype.hasOwnProperty.call(out, kv[0])) throw new YamlError(`duplicate key "${kv[0]}"`, l.n);
      out[kv[0]] = valueAfter(kv[1], indent, l.n);
    }
    return out;
  }

  function parseSeq(indent) {
    const out = [];
    while (pos < lines.length) {
      skipBlank();
      if (pos >= lines.length) break;
      const l = lines[pos];
      const i = indentOf(l);
      const c = content(l).trim();
      if (i < indent || !(c.startsWith("- ") || c === "-")) break;
      if (i > indent) throw new YamlError("unexpected indentation", l.n);
      const rest = c === "-" ? "" : c.slice(2);
      if (rest.trim() === "") {
        pos++;
        out.push(valueAfter("", indent, l.n));
        continue;
      }
      const kv = /^[[{"']/.test(rest.trim()) ? null : splitKey(rest, l.n);
      if (kv) {
        // "- key: value" starts a mapping whose keys sit at the column after "- "
        const col = i + 2 + (rest.length - rest.trimStart().length);
        lines[pos] = { raw: " ".repeat(col) + rest.trimStart(), n: l.n };
        out.push(parseMap(col));
      } else {
        pos++;
        out.push(/^[|>][-+]?$/.test(rest.trim()) ? blockScalar(rest.trim(), indent) : scalar(rest, l.n));
      }
    }
    return out;
  }

  skipBlank();
  if (pos >= lines.length) return null;
  const v = parseBlock(0);
  skipBlank();
  if (pos < lines.length) throw new YamlError("unexpected content (check the indentation)", lines[pos].n);
  return v;
}

const PLAIN = /^[A-Za-z_][A-Za-z0-9_. /()+-]*$/;
function yScalar(v) {
  if (v === null || v === undefined) return "null";
  if (typeof v === "number") return Number.isFinite(v) ? String(v) : v > 0 ? ".inf" : v < 0 ? "-.inf" : ".nan";
  if (typeof v === "boolean") return String(v);
  const s = String(v);
  if (PLAIN.test(s) && !/^(true|false|null|yes|no|on|off|~)$/i.test(s) && !/: |\s$/.test(s)) return s;
  return JSON.stringify(s);
}

/** Write a value as block YAML. */
export function toYaml(v, indent = 0) {
  const pad = " ".repeat(indent);
  if (Array.isArray(v)) {
    if (!v.length) return "[]";
    if (v.every((x) => x === null || typeof x !== "object")) return `[${v.map(yScalar).join(", ")}]`;
    return v.map((x) => {
      if (x && typeof x === "object" && !Array.isArray(x) && Object.keys(x).length) {
        const inner = toYaml(x, indent + 2).replace(/^ +/, "");
        return `${pad}- ${inner}`;
      }
      return `${pad}- ${toYaml(x, indent + 2)}`;
    }).join("\n");
  }
  if (v && typeof v === "object") {
    const keys = Object.keys(v);
    if (!keys.length) return "{}";
    return keys.map((k) => {
      const x = v[k];
      const key = PLAIN.test(k) ? k : JSON.stringify(k);
      if (x && typeof x === "object" && (Array.isArray(x) ? x.some((y) => y && typeof y === "object") : Object.keys(x).length)) {
        return `${pad}${key}:\n${toYaml(x, indent + 2)}`;
      }
      return `${pad}${key}: ${toYaml(x, indent + 2)}`;
    }).join("\n");
  }
  return yScalar(v);
}
