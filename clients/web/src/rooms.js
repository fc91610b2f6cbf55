// Rooms from the plan: the polygon a double-click inside closed walls fills, and a room's area. In:
// walls ({start, end, thickness}) in plan metres. Out: polygons [[x, z], ...] to the millimetre.
// Walls meet where their ends coincide (to the millimetre); a wall ending in the middle of another
// makes no corner there, so a room closed that way is not found.
import { pointInPolygon } from "./plan_math.js";
import { mm, roundPoint } from "./plan_point.js";

const key = (p) => roundPoint(p).join(",");

// Signed area, positive for a polygon counter-clockwise with x right and z up (clockwise on screen).
export function signedArea(points) {
  let a = 0;
  for (let i = 0, j = points.length - 1; i < points.length; j = i++) a += points[j][0] * points[i][1] - points[i][0] * points[j][1];
  return a / 2;
}

export const polygonArea = (points) => Math.abs(signedArea(points));

// The faces of the walls' plan graph: each a cycle of corners with the wall along each side.
function faces(walls) {
  const corners = new Map();  // key -> {p, out: [{to, wall, angle}]}
  const corner = (p) => {
    const k = key(p);
    if (!corners.has(k)) corners.set(k, { p: roundPoint(p), k, out: [] });
    return corners.get(k);
  };
  for (const w of walls) {
    if (!Array.isArray(w?.start) || !Array.isArray(w?.end)) continue;
    const a = corner(w.start);
    const b = corner(w.end);
    if (a === b) continue;
    a.out.push({ to: b, wall: w, angle: Math.atan2(b.p[1] - a.p[1], b.p[0] - a.p[0]) });
    b.out.push({ to: a, wall: w, angle: Math.atan2(a.p[1] - b.p[1], a.p[0] - b.p[0]) });
  }
  for (const c of corners.values()) c.out.sort((x, y) => x.angle - y.angle);
  const seen = new Set();
  const result = [];
  for (const c of corners.values()) {
    for (const first of c.out) {
      if (seen.has(`${c.k}>${first.to.k}`)) continue;
      const cycle = [];
      let from = c;
      let edge = first;
      for (let guard = 0; guard < 4 * walls.length + 4; guard++) {
        const id = `${from.k}>${edge.to.k}`;
        if (seen.has(id)) break;
        seen.add(id);
        cycle.push({ p: from.p, wall: edge.wall });
        // At the far corner, the next side is the one just before the way back in angle order.
        const at = edge.to;
        const back = at.out.findIndex((o) => o.to === from && o.wall === edge.wall);
        const next = at.out[(back - 1 + at.out.length) % at.out.length];
        from = at;
        edge = next;
      }
      if (cycle.length >= 3 && from === c) result.push(cycle);
    }
  }
  return result;
}

// The room a double-click at p fills: the smallest face of the walls around p, drawn to the walls'
// inner faces (each side moved inward by half its wall's thickness), counter-clockwise with x right
// and z up; null when no closed walls surround p.
export function roomAt(walls, p) {
  let best = null;
  for (const cycle of faces(walls || [])) {
    const pts = cycle.map((c) => c.p);
    if (!pointInPolygon(p, pts)) continue;
    const area = polygonArea(pts);
    if (area > 1e-9 && (!best || area < best.area)) best = { cycle, area };
  }
  if (!best) return null;
  let cycle = best.cycle;
  if (signedArea(cycle.map((c) => c.p)) < 0) {
    // Reversed: the same corners the other way round, each side keeping its wall.
    const n = cycle.length;
    cycle = cycle.map((_, i) => ({ p: cycle[(n - i) % n].p, wall: cycle[(2 * n - i - 1) % n].wall }));
  }
  const n = cycle.length;
  const lines = cycle.map((c, i) => {
    const a = c.p;
    const b = cycle[(i + 1) % n].p;
    const len = Math.hypot(b[0] - a[0], b[1] - a[1]);
    const d = [(b[0] - a[0]) / len, (b[1] - a[1]) / len];
    const half = (c.wall.thickness ?? 0.15) / 2;
    const normal = [-d[1], d[0]];  // the inside, left of a counter-clockwise side
    return { a: [a[0] + normal[0] * half, a[1] + normal[1] * half], d };
  });
  return lines.map((l, i) => {
    const prev = lines[(i - 1 + n) % n];
    const cross = prev.d[0] * l.d[1] - prev.d[1] * l.d[0];
    if (Math.abs(cross) < 1e-9) return [mm(l.a[0]), mm(l.a[1])];  // straight on: the shifted corner
    const t = ((l.a[0] - prev.a[0]) * l.d[1] - (l.a[1] - prev.a[1]) * l.d[0]) / cross;
    return [mm(prev.a[0] + prev.d[0] * t), mm(prev.a[1] + prev.d[1] * t)];
  });
}
