// The designer's furniture: a block (box) and a cylinder, and the models of the server's catalogue
// (GET /v1/catalogue: Sweet Home 3D's, each a piece whose parts name read-only stored meshes). In:
// an item's id and a plan point [x, z] (metres). Out: one solid of the scene format standing there.

// The items that need no server: a block of 0.5 m and a cylinder.
const primitives = {
  box: { name: "Block", make: (id, at) => ({ type: "box", id, center: at, size: [0.5, 0.5, 0.5], color: "#b0b0b0" }) },
  cylinder: { name: "Cylinder", make: (id, at) => ({ type: "cylinder", id, center: at, radius: 0.25, height: 0.5, color: "#9aa8b8" }) },
};

export const primitiveItems = Object.keys(primitives);

// The catalogue's entries by id, from its answer (empty without one).
export function catalogueEntries(answer) {
  return new Map((answer?.items || []).map((item) => [item.id, item]));
}

// A new solid for `item` (a primitive or a catalogue entry's id) centred on `at`; `id` names it in
// warnings. A catalogue entry is its piece, at its real size and elevation. null for an unknown item.
export function makeFurniture(item, at, id, entries = new Map()) {
  if (primitives[item]) return primitives[item].make(id, at);
  const entry = entries.get(item);
  if (!entry) return null;
  const { type, ...rest } = entry.piece;
  return { type, id, center: at, rotation_y: 0, ...rest };
}

// The categories of the catalogue in the order their first entries come.
export function categories(entries) {
  return [...new Set([...entries.values()].map((e) => e.category))];
}
