// Hash-route helpers shared by the shell and the views.

/** Parse "#/path?a=1&b=2" into {path, query}. */
export function parseHash(hash = location.hash) {
  const s = hash.replace(/^#/, "");
  const i = s.indexOf("?");
  const path = i < 0 ? s : s.slice(0, i);
  const query = Object.fromEntries(new URLSearchParams(i < 0 ? "" : s.slice(i + 1)));
  return { path: path || "/", query };
}

/** Change the query of the current route without re-rendering (shareable view state). */
export function replaceQuery(query) {
  const { path } = parseHash();
  const qs = new URLSearchParams(Object.entries(query)
    .filter(([, v]) => v !== undefined && v !== null && v !== "")).toString();
  history.replaceState(null, "", `#${path}${qs ? `?${qs}` : ""}`);
}

/** Go to a route. */
export function go(hash) {
  location.hash = hash.startsWith("#") ? hash : `#${hash}`;
}
