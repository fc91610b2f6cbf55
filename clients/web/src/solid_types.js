// The solid types of a scene's "solids", one row each in the order of the renderer's solid table
// (render/core/solids.cpp; each type's members are read in render/scene_io/solid_readers.cpp):
// footprint(s), its outline in the plan ({polygon} or {circle: {center, radius}}); anchor(s), the
// plan point it is moved by; move(s, to, d), the solid with its anchor moved by d to `to`; fields(s),
// its own fields in the properties panel (colour, which every type has, is added by the panel);
// for types sized by a box, handles(s), the plan points of its corner handles, and
// resize(s, k, p, keepProportions), the solid with handle k dragged to p. A
// type the page does not know is drawn as nothing and edited as a centred solid (solidType).
import { mm, roundPoint, placePoint } from "./plan_point.js";
import { num, positive } from "./fields.js";

function boxCorners(sx, sz, rotation, center) {
  return [[-sx / 2, -sz / 2], [sx / 2, -sz / 2], [sx / 2, sz / 2], [-sx / 2, sz / 2]].map((q) => placePoint(q, rotation, center));
}

const unitBox = [[-0.5, 0, -0.5], [0.5, 0, 0.5]];

// The footprint of a mesh: its vertices' bounds in x and z, scaled, turned and placed.
function meshFootprint(s) {
  const scale = Array.isArray(s.scale) ? s.scale : [s.scale ?? 1, s.scale ?? 1, s.scale ?? 1];
  // Loops, not Math.min(...xs): an imported mesh can have more vertices than a call has arguments.
  const lo = [Infinity, Infinity];
  const hi = [-Infinity, -Infinity];
  // A mesh placed by `ref` carries no vertices here; a stored furniture model is the unit box
  // centred on the origin (its scale is the piece's size), so that box stands in for it.
  for (const v of Array.isArray(s.vertices) ? s.vertices : s.ref ? unitBox : []) {
    const x = v[0] * scale[0];
    const z = v[2] * scale[2];
    if (x < lo[0]) lo[0] = x;
    if (x > hi[0]) hi[0] = x;
    if (z < lo[1]) lo[1] = z;
    if (z > hi[1]) hi[1] = z;
  }
  if (!(lo[0] <= hi[0] && lo[1] <= hi[1])) return { polygon: [] };
  const pos = s.position || [0, 0, 0];
  const corners = [[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]];
  return { polygon: corners.map((q) => placePoint(q, s.rotation_y || 0, [pos[0], pos[2]])) };
}

const rotation = (s) => num("rotation (°)", ["rotation_y"], s.rotation_y ?? 0, { step: 15 });
const size = (s) => [num("width", ["size", 0], s.size[0], positive), num("height", ["size", 1], s.size[1], positive),
  num("depth", ["size", 2], s.size[2], positive)];

// Placed by center (x, z) and base, turned by rotation_y.
const centred = {
  footprint: () => ({ polygon: [] }),
  anchor: (s) => s.center,
  move: (s, to) => ({ ...s, center: roundPoint(to) }),
  fields: (s) => [num("x", ["center", 0], s.center[0]), num("z", ["center", 1], s.center[1]),
    num("base", ["base"], s.base ?? 0), rotation(s)],
};

// The smallest width or depth a corner handle leaves a solid (metres).
const minSide = 0.05;
const cm = (v) => Math.round(v * 100) / 100;
const cornerSigns = [[-1, -1], [1, -1], [1, 1], [-1, 1]];  // boxCorners' order

// The solid with its footprint corner k on plan point p and the opposite corner where it was: width
// and depth follow the pointer in the solid's own frame (whole centimetres, at least minSide); with
// keepProportions, the pointer's reach along the diagonal scales width, height and depth together.
function resizeBox(s, k, p, keepProportions) {
  const r = ((s.rotation_y || 0) * Math.PI) / 180;
  const c = Math.cos(r);
  const sn = Math.sin(r);
  const dx = p[0] - s.center[0];
  const dz = p[1] - s.center[1];
  const local = [dx * c - dz * sn, dx * sn + dz * c];  // placePoint undone
  const [gx, gz] = cornerSigns[k];
  const fixed = [(-gx * s.size[0]) / 2, (-gz * s.size[2]) / 2];
  const reach = [gx * (local[0] - fixed[0]), gz * (local[1] - fixed[1])];
  let size;
  if (keepProportions) {
    const f = (reach[0] * s.size[0] + reach[1] * s.size[2]) / (s.size[0] ** 2 + s.size[2] ** 2);
    const g = Math.max(f, minSide / Math.min(s.size[0], s.size[2]));
    size = s.size.map((v) => cm(v * g));
  } else {
    size = [cm(Math.max(minSide, reach[0])), s.size[1], cm(Math.max(minSide, reach[1]))];
  }
  const centre = placePoint([fixed[0] + (gx * size[0]) / 2, fixed[1] + (gz * size[2]) / 2], s.rotation_y || 0, s.center);
  return { ...s, center: roundPoint(centre), size };
}

// Sized by a box: corner handles in the plan resize it (handles, resize).
const boxLike = {
  ...centred,
  footprint: (s) => ({ polygon: boxCorners(s.size[0], s.size[2], s.rotation_y || 0, s.center) }),
  fields: (s) => [...centred.fields(s), ...size(s)],
  handles: (s) => boxCorners(s.size[0], s.size[2], s.rotation_y || 0, s.center),
  resize: resizeBox,
};

// A piece of furniture: its parts fill its box, placed as a box is, so it is drawn, moved, turned and
// sized as one; mirrored flips it across its width.
const piece = {
  ...boxLike,
  fields: (s) => [...boxLike.fields(s), { label: "mirrored", path: ["mirrored"], kind: "bool", value: Boolean(s.mirrored) }],
};

export const solidTypes = {
  box: boxLike,
  cylinder: {
    ...centred,
    footprint: (s) => ({ circle: { center: s.center, radius: s.radius } }),
    fields: (s) => [...centred.fields(s), num("radius", ["radius"], s.radius, positive), num("height", ["height"], s.height, positive)],
  },
  pyramid: boxLike,
  prism: {
    footprint: (s) => ({ polygon: s.points }),
    anchor: (s) => {
      const n = s.points.length;
      return [s.points.reduce((a, p) => a + p[0], 0) / n, s.points.reduce((a, p) => a + p[1], 0) / n];
    },
    move: (s, to, d) => ({ ...s, points: s.points.map((q) => roundPoint([q[0] + d[0], q[1] + d[1]])) }),
    fields: (s) => [num("height", ["height"], s.height, positive)],  // its points are placed already
  },
  mesh: {
    footprint: meshFootprint,
    anchor: (s) => [(s.position || [0, 0, 0])[0], (s.position || [0, 0, 0])[2]],
    move: (s, to, d) => {
      const p = s.position || [0, 0, 0];
      return { ...s, position: [mm(p[0] + d[0]), p[1], mm(p[2] + d[1])] };
    },
    fields: (s) => {
      const p = s.position || [0, 0, 0];
      return [num("x", ["position", 0], p[0]), num("z", ["position", 2], p[2]), num("elevation", ["position", 1], p[1]),
        rotation(s)];
    },
  },
  piece,
};

// The row of a solid's type (a centred solid without a footprint for a type the page does not know).
export const solidType = (s) => (Object.prototype.hasOwnProperty.call(solidTypes, s.type) ? solidTypes[s.type] : centred);
