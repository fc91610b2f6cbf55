// Small helpers of the designer's modules: reading and writing a request by JSON Pointer (plain
// "/a/0/b" pointers of the designer's own making: no "~" escapes), and deep copies of JSON values.
export const clone = (v) => JSON.parse(JSON.stringify(v));

// The element a pointer names inside the request, or undefined.
export function at(request, pointer) {
  let v = request;
  for (const t of pointer.split("/").slice(1)) v = v == null ? undefined : v[t];
  return v;
}

// Sets the value at a pointer relative to `root` (its parent must exist).
export function setAt(root, pointer, value) {
  const tokens = pointer.split("/").slice(1);
  let parent = root;
  for (const t of tokens.slice(0, -1)) parent = parent[t];
  parent[tokens[tokens.length - 1]] = value;
}
