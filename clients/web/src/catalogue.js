// The designer's furniture catalogue. In: an item name and a plan point [x, z] (metres). Out: one
// solid of the scene format standing on the floor there. Box, cylinder and wardrobe are plain
// `box`/`cylinder` solids; the others are one closed `mesh` made of boxes (legs, top, back...), so
// each piece of furniture stays one element to select, move and rotate. Sizes are common real-world
// ones, listed in clients/README.md ("Furniture catalogue").

// [x0, y0, z0, x1, y1, z1] boxes in the item's own space: origin at the centre of its footprint on
// the floor, +Y up, the front toward +Z.
function legs(w, d, h, t, inset = 0) {
  const x = w / 2 - inset;
  const z = d / 2 - inset;
  return [[-x, 0, -z, -x + t, h, -z + t], [x - t, 0, -z, x, h, -z + t],
    [-x, 0, z - t, -x + t, h, z], [x - t, 0, z - t, x, h, z]];
}

const parts = {
  // 1.20 × 0.80 m, 0.75 m high: a 4 cm top on four 5 cm legs.
  table: () => [[-0.6, 0.71, -0.4, 0.6, 0.75, 0.4], ...legs(1.2, 0.8, 0.71, 0.05, 0.03)],
  // 0.45 × 0.45 m seat at 0.45 m, back up to 0.90 m at the rear (−Z).
  chair: () => [[-0.225, 0.41, -0.225, 0.225, 0.45, 0.225], ...legs(0.45, 0.45, 0.41, 0.04),
    [-0.225, 0.45, -0.225, 0.225, 0.9, -0.185]],
  // 1.60 × 2.00 m double bed: 0.45 m base and mattress, 1.00 m headboard at the rear (−Z).
  bed: () => [[-0.8, 0, -0.94, 0.8, 0.45, 1.0], [-0.8, 0, -1.0, 0.8, 1.0, -0.94]],
  // 2.00 × 0.90 m sofa: 0.42 m seat, 0.80 m back, 0.60 m arms.
  sofa: () => [[-0.85, 0, -0.25, 0.85, 0.42, 0.45], [-1.0, 0, -0.45, 1.0, 0.8, -0.25],
    [-1.0, 0, -0.25, -0.85, 0.6, 0.45], [0.85, 0, -0.25, 1.0, 0.6, 0.45]],
  // Floor lamp 1.70 m: 0.30 m square foot, 3 cm pole, 0.35 m shade from 1.40 m.
  lamp: () => [[-0.15, 0, -0.15, 0.15, 0.03, 0.15], [-0.015, 0.03, -0.015, 0.015, 1.4, 0.015],
    [-0.175, 1.4, -0.175, 0.175, 1.7, 0.175]],
};

const colors = { box: "#b0b0b0", cylinder: "#9aa8b8", table: "#8b6b4a", chair: "#a0522d", bed: "#6b8caf",
  sofa: "#7a8a6a", wardrobe: "#b89b72", lamp: "#e8d9a0" };

export const catalogueItems = ["box", "cylinder", "table", "chair", "bed", "sofa", "wardrobe", "lamp"];

// Eight corners and six quads of each box, every quad counter-clockwise seen from outside (as the
// format wants of a closed mesh).
function boxesToMesh(boxes) {
  const vertices = [];
  const faces = [];
  for (const [x0, y0, z0, x1, y1, z1] of boxes) {
    const b = vertices.length;
    for (const z of [z0, z1]) for (const y of [y0, y1]) for (const x of [x0, x1]) vertices.push([x, y, z]);
    // corner index = x + 2y + 4z (each 0 or 1)
    for (const f of [[0, 4, 6, 2], [1, 3, 7, 5], [0, 1, 5, 4], [2, 6, 7, 3], [0, 2, 3, 1], [4, 5, 7, 6]]) {
      faces.push(f.map((i) => b + i));
    }
  }
  const round = (v) => Math.round(v * 1000) / 1000 + 0;
  return { vertices: vertices.map((v) => v.map(round)), faces };
}

// A new solid for `item` with its footprint centred on `at`; `id` names it in warnings.
export function makeFurniture(item, at, id) {
  const color = colors[item];
  if (item === "box") return { type: "box", id, center: at, size: [0.5, 0.5, 0.5], color };
  if (item === "cylinder") return { type: "cylinder", id, center: at, radius: 0.25, height: 0.5, color };
  if (item === "wardrobe") return { type: "box", id, center: at, size: [1.0, 2.0, 0.6], color };
  const mesh = boxesToMesh(parts[item]());
  return { type: "mesh", id, position: [at[0], 0, at[1]], rotation_y: 0, closed: true, color, ...mesh };
}

// The catalogue item an element was made from, read back from its id ("chair-2" -> "chair").
export function itemOf(solid) {
  const m = /^([a-z]+)-\d+$/.exec(solid.id || "");
  return m && catalogueItems.includes(m[1]) ? m[1] : null;
}
