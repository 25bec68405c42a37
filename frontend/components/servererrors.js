// The server's 422 items placed at the form: each item's `loc` mapped to the nearest rendered field
// or block, and the note shown on a block that is not a field.

import { h } from "./dom.js";

/** A string quoted for a CSS attribute selector. */
export function cssEsc(s) {
  return window.CSS?.escape ? CSS.escape(s) : s.replace(/"/g, '\\"');
}

/** The element of the block whose data-path is `key`, or null. */
export function blockAt(el, key) {
  return el.querySelector(`[data-path="${cssEsc(key)}"]`);
}

/** Dotted path of an item's loc, without the leading "body" / "scenario". */
function locKey(loc) {
  let parts = (loc || []).map(String);
  while (parts.length && ["body", "scenario"].includes(parts[0])) parts = parts.slice(1);
  return parts.join(".");
}

/** The nearest key at or above `key` that `isShown` accepts, or "". */
function nearestKey(key, isShown) {
  while (key && !isShown(key)) key = key.includes(".") ? key.slice(0, key.lastIndexOf(".")) : "";
  return key;
}

/**
 * Place 422 items: {errors: Map key → message (joined with "; "), unmatched: items not at a field}.
 * `isField(key)` tells a rendered field, `isShown(key)` a rendered field or block.
 */
export function placeServerErrors(items, isField, isShown) {
  const errors = new Map();
  const unmatched = [];
  for (const it of items || []) {
    const msg = String(it.msg || "");
    const key = nearestKey(locKey(it.loc), isShown);
    if (!key) {
      unmatched.push({ ...it, msg });
      continue;
    }
    const prev = errors.get(key);
    errors.set(key, prev ? `${prev}; ${msg}` : msg);
    if (!isField(key)) unmatched.push({ ...it, msg, path: key });
  }
  return { errors, unmatched };
}

/** Show a server message on the block at `key` (not a field) and open its group. */
export function markBlock(el, key, msg) {
  const block = blockAt(el, key);
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
