// Paths into a scenario value (["vehicle", "bodies", 0, "mass"]): reading, writing, deleting,
// and the key and element id the form gives them.

/** Dotted key of a path: "vehicle.bodies.0.mass". */
export function pathKey(path) {
  return path.join(".");
}

/** Element id of the field at a path: "f-vehicle-bodies-0-mass". */
export function fieldId(path) {
  return `f-${path.join("-").replace(/[^A-Za-z0-9_-]/g, "_")}`;
}

/** The value at a path, or undefined where the path runs out. */
export function getAt(root, path) {
  let v = root;
  for (const p of path) {
    if (v === null || v === undefined) return undefined;
    v = v[p];
  }
  return v;
}

/** Set the value at a path, making the objects (or arrays, for numeric steps) on the way. */
export function setAt(root, path, val) {
  let v = root;
  for (let i = 0; i < path.length - 1; i++) {
    const p = path[i];
    if (v[p] === null || v[p] === undefined || typeof v[p] !== "object") v[p] = typeof path[i + 1] === "number" ? [] : {};
    v = v[p];
  }
  v[path[path.length - 1]] = val;
}

/** Remove the key at the end of a path from its parent, if the parent exists. */
export function deleteAt(root, path) {
  const parent = getAt(root, path.slice(0, -1));
  if (parent && typeof parent === "object") delete parent[path[path.length - 1]];
}
