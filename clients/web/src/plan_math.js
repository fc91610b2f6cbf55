// Plan geometry for the designer. In: scene elements as the request holds them (docs/scene-format.md),
// plan points [x, z] in metres. Out: footprints as plan polygons, hit tests, snapping and the checks an
// opening must pass before it is added. Pure functions; no DOM. rotation_y turns counter-clockwise
// seen from above (+X toward −Z), as the format says.

import { mm, roundPoint, placePoint } from "./plan_point.js";
import { solidType } from "./solid_types.js";
import { onLevel } from "./levels.js";

export { roundPoint, placePoint };

export const gridStepM = 0.1;    // wall points and drops snap to this grid
export const angleStepDeg = 15;  // wall directions snap to these steps

export const snapToGrid = (p, step = gridStepM) => roundPoint([Math.round(p[0] / step) * step, Math.round(p[1] / step) * step]);
export const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);

// Where the next wall point goes: onto an existing wall end within `endTolM`, else (from `from`) along
// the nearest 15° direction with its length on the grid, else onto the grid.
export function snapWallPoint(p, from, ends, endTolM) {
  let best = null;
  for (const e of ends) {
    const d = distance(p, e);
    if (d <= endTolM && (!best || d < best.d)) best = { d, e };
  }
  if (best) return roundPoint(best.e);
  if (!from) return snapToGrid(p);
  const length = Math.round(distance(p, from) / gridStepM) * gridStepM;
  const angle = Math.atan2(p[1] - from[1], p[0] - from[0]);
  const step = (angleStepDeg * Math.PI) / 180;
  const snapped = Math.round(angle / step) * step;
  return roundPoint([from[0] + length * Math.cos(snapped), from[1] + length * Math.sin(snapped)]);
}

export const wallEnds = (walls) => (walls || []).filter((w) => wallLength(w) > 0).flatMap((w) => [w.start, w.end]);

// 0 for a wall whose ends are not (yet) two points: the text may be half-typed.
export function wallLength(w) {
  return Array.isArray(w.start) && Array.isArray(w.end) ? distance(w.start, w.end) : 0;
}

// The wall's box in plan: four corners around its centreline (no mitres).
export function wallPolygon(w) {
  const len = wallLength(w) || 1;
  const half = (w.thickness ?? 0.15) / 2;
  const nx = (-(w.end[1] - w.start[1]) / len) * half;
  const nz = ((w.end[0] - w.start[0]) / len) * half;
  return [[w.start[0] + nx, w.start[1] + nz], [w.end[0] + nx, w.end[1] + nz],
    [w.end[0] - nx, w.end[1] - nz], [w.start[0] - nx, w.start[1] - nz]];
}

// The opening's stretch of wall, as a plan polygon of the wall's thickness.
export function openingPolygon(w, o) {
  const len = wallLength(w) || 1;
  const ux = (w.end[0] - w.start[0]) / len;
  const uz = (w.end[1] - w.start[1]) / len;
  const a = [w.start[0] + ux * o.offset, w.start[1] + uz * o.offset];
  const b = [a[0] + ux * o.width, a[1] + uz * o.width];
  return wallPolygon({ start: a, end: b, thickness: (w.thickness ?? 0.15) + 0.02 });
}

// Distance along the centreline of the point nearest to p, and how far p is from it.
export function projectOnWall(w, p) {
  const len = wallLength(w);
  const ux = (w.end[0] - w.start[0]) / len;
  const uz = (w.end[1] - w.start[1]) / len;
  const t = Math.max(0, Math.min(len, (p[0] - w.start[0]) * ux + (p[1] - w.start[1]) * uz));
  const q = [w.start[0] + ux * t, w.start[1] + uz * t];
  return { t, off: distance(p, q) };
}

// A solid's footprint: {polygon} or {circle: {center, radius}} (solid_types.js).
export function solidFootprint(s) {
  return solidType(s).footprint(s);
}

// The footprint, or null for a solid that lacks the members it needs (half-typed in the editor).
export function footprintOrNull(s) {
  try {
    return solidFootprint(s);
  } catch {
    return null;
  }
}

// The plan point a solid is moved by: center, or position's x and z for a mesh (solid_types.js).
export function solidAnchor(s) {
  return solidType(s).anchor(s);
}

// The solid moved so its anchor lands on `to` (a new object; the input is left alone).
export function moveSolid(s, to) {
  const from = solidAnchor(s);
  return solidType(s).move(s, to, [to[0] - from[0], to[1] - from[1]]);
}

// The plan points of a solid's resize handles (none for a type not sized by a box).
export function resizeHandles(s) {
  const type = solidType(s);
  return type.handles && Array.isArray(s.size) && Array.isArray(s.center) ? type.handles(s) : [];
}

// The solid with resize handle k dragged to plan point p (a new object; see solid_types.js).
export function resizeSolid(s, k, p, keepProportions = false) {
  return solidType(s).resize(s, k, p, keepProportions);
}

export function pointInPolygon(p, poly) {
  let inside = false;
  for (let i = 0, j = poly.length - 1; i < poly.length; j = i++) {
    const [xi, zi] = poly[i];
    const [xj, zj] = poly[j];
    if ((zi > p[1]) !== (zj > p[1]) && p[0] < ((xj - xi) * (p[1] - zi)) / (zj - zi) + xi) inside = !inside;
  }
  return inside;
}

// The JSON Pointer of the element under plan point p (within tolM metres), topmost first: lights,
// openings, solids (later drawn above earlier), walls. null when nothing is there. With `level` (a
// level's id), elements on other levels are not there (levels.js).
export function hitTest(scene, p, tolM, level = null) {
  const lights = scene.lights || [];
  for (let i = lights.length - 1; i >= 0; i--) {
    const l = lights[i];
    if (!onLevel(l, level)) continue;
    if (l.type === "point" && Array.isArray(l.position) && distance(p, [l.position[0], l.position[2]]) <= Math.max(tolM, 0.15)) return `/scene/lights/${i}`;
  }
  const walls = scene.walls || [];
  for (let i = 0; i < walls.length; i++) {
    const w = walls[i];
    if (!wallLength(w) || !onLevel(w, level)) continue;
    const { t, off } = projectOnWall(w, p);
    if (off > (w.thickness ?? 0.15) / 2 + tolM) continue;
    const k = (w.openings || []).findIndex((o) => t >= o.offset && t <= o.offset + o.width);
    if (k >= 0) return `/scene/walls/${i}/openings/${k}`;
  }
  const solids = scene.solids || [];
  for (let i = solids.length - 1; i >= 0; i--) {
    const f = onLevel(solids[i], level) ? footprintOrNull(solids[i]) : null;
    if (!f) continue;
    if (f.circle && distance(p, f.circle.center) <= f.circle.radius + tolM) return `/scene/solids/${i}`;
    if (f.polygon && f.polygon.length >= 3 && pointInPolygon(p, f.polygon)) return `/scene/solids/${i}`;
  }
  let best = null;
  walls.forEach((w, i) => {
    if (!wallLength(w) || !onLevel(w, level)) return;
    const { off } = projectOnWall(w, p);
    if (off <= (w.thickness ?? 0.15) / 2 + tolM && (!best || off < best.off)) best = { off, i };
  });
  return best ? `/scene/walls/${best.i}` : null;
}

// Why `opening` cannot go into `wall` (the server's rules from docs/scene-format.md), or null when it
// fits. `skip` is the index of an opening of the same wall to leave out (the one being edited).
export function openingProblem(wall, opening, skip = -1) {
  const len = wallLength(wall);
  const wallHeight = wall.height ?? 2.5;
  const height = opening.height ?? (opening.type === "door" ? 2.0 : 1.2);
  const sill = opening.type === "window" ? opening.sill ?? 0.9 : 0;
  if (opening.width > len + 1e-9) return `a ${opening.width} m wide ${opening.type} does not fit in a ${mm(len)} m wall`;
  if (opening.offset < -1e-9 || opening.offset + opening.width > len + 1e-9) {
    return `offset + width (${mm(opening.offset + opening.width)} m) is beyond the wall's length (${mm(len)} m)`;
  }
  if (sill + height > wallHeight + 1e-9) {
    return `${opening.type === "window" ? "sill + height" : "height"} (${mm(sill + height)} m) is above the wall's height (${wallHeight} m)`;
  }
  const clash = (wall.openings || []).findIndex((o, k) => k !== skip &&
    opening.offset < o.offset + o.width - 1e-9 && o.offset < opening.offset + opening.width - 1e-9);
  if (clash >= 0) return `it would overlap the wall's ${wall.openings[clash].type} ${wall.openings[clash].id || `#${clash}`}`;
  return null;
}

// An opening of `width` centred on distance t along the wall (t on a 5 cm step, as a pointer is
// not more precise), slid inward to stay within the wall.
export function openingAt(wall, tClicked, fields) {
  const len = wallLength(wall);
  const t = Math.round(tClicked / 0.05) * 0.05;
  const offset = Math.max(0, Math.min(len - fields.width, t - fields.width / 2));
  return { ...fields, offset: mm(Math.max(0, offset)) };
}

// Plan bounds of everything drawn: [[minX, minZ], [maxX, maxZ]], or null for an empty scene.
export function sceneBounds(scene) {
  const pts = [];
  for (const w of scene.walls || []) if (wallLength(w)) pts.push(w.start, w.end);
  for (const s of scene.solids || []) {
    const f = footprintOrNull(s);
    if (!f) continue;
    if (f.circle) pts.push([f.circle.center[0] - f.circle.radius, f.circle.center[1] - f.circle.radius],
      [f.circle.center[0] + f.circle.radius, f.circle.center[1] + f.circle.radius]);
    else pts.push(...(f.polygon || []));
  }
  for (const l of scene.lights || []) if (l.type === "point" && Array.isArray(l.position)) pts.push([l.position[0], l.position[2]]);
  for (const r of scene.rooms || []) if (Array.isArray(r?.points)) pts.push(...r.points.filter(isPoint));
  if (scene.floor && Array.isArray(scene.floor.cells)) {
    const o = scene.floor.origin || [0, 0];
    const c = scene.floor.cell_size ?? 1;
    pts.push(o, [o[0] + scene.floor.cells[0] * c, o[1] + scene.floor.cells[1] * c]);
  }
  const finite = pts.filter(isPoint);
  if (!finite.length) return null;
  const lo = [Infinity, Infinity];
  const hi = [-Infinity, -Infinity];
  for (const [x, z] of finite) {
    lo[0] = Math.min(lo[0], x);
    lo[1] = Math.min(lo[1], z);
    hi[0] = Math.max(hi[0], x);
    hi[1] = Math.max(hi[1], z);
  }
  return [lo, hi];
}

function isPoint(p) {
  return Array.isArray(p) && Number.isFinite(p[0]) && Number.isFinite(p[1]);
}

// Walls with every end that lies on a `from` point (within 1e-6 m, as the format joins them) put on
// its `to` point: moving a corner moves the ends of all the walls that meet there.
export function moveWallEnds(walls, moves) {
  const moved = (p) => {
    const m = moves.find((mv) => distance(p, mv.from) < 1e-6);
    return m ? roundPoint(m.to) : p;
  };
  return walls.map((w) => {
    const start = moved(w.start);
    const end = moved(w.end);
    return start === w.start && end === w.end ? w : { ...w, start, end };
  });
}

// The first opening that no longer fits its wall, as "/scene/walls/i/openings/k: reason", or null.
export function wallsProblem(walls) {
  for (let i = 0; i < walls.length; i++) {
    const w = walls[i];
    if (distance(w.start, w.end) < 1e-6) return `wall ${i} would have no length`;
    for (let k = 0; k < (w.openings || []).length; k++) {
      const problem = openingProblem(w, w.openings[k], k);
      if (problem) return `the ${w.openings[k].type} of wall ${i}: ${problem}`;
    }
  }
  return null;
}
