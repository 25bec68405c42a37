// The form's problem reports: the summary list above the form and the count on each group.

import { h } from "./dom.js";

const plural = (n, word) => `${n} ${word}${n > 1 ? "s" : ""}`;

/**
 * Fill the summary element with up to 20 problems [{path, msg}], or hide it when there are none.
 * `hrefOf(path)` is the anchor of a rendered field (null if none); `onPick(path)` focuses it.
 */
export function showSummary(summaryEl, problems, title, hrefOf, onPick) {
  if (!problems.length) {
    summaryEl.hidden = true;
    return;
  }
  const item = (p) => {
    const href = hrefOf(p.path);
    const name = href ? h("a", { href, onclick: (e) => {
      e.preventDefault();
      onPick(p.path);
    } }, p.path) : h("code", {}, p.path || "scenario");
    return h("li", {}, name, `: ${p.msg}`);
  };
  summaryEl.hidden = false;
  summaryEl.replaceChildren(
    h("strong", {}, title || `${plural(problems.length, "problem")} to fix before submitting:`),
    h("ul", {}, problems.slice(0, 20).map(item)));
}

/** Write the number of invalid fields in each group's summary line. */
export function updateGroupCounts(formEl) {
  for (const det of formEl.querySelectorAll("details[data-group]")) {
    const n = det.querySelectorAll(".field.invalid, .enumset.invalid").length;
    det.querySelector(".group-errors").textContent = n ? plural(n, "problem") : "";
  }
}
