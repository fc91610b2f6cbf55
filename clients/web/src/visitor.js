// The visitor of walk mode: where it starts and how far a step may take it. In: the request's scene
// (walls with their openings, rooms), plan points [x, z] in metres and the eye's height y. Out: plan
// points. Walls stop the visitor, a body of `bodyRadiusM` around the eye, except across a door
// opening (leaf or not: a visitor opens doors); windows and the rest of the wall stop it. Walls count
// when they stand at the height of the body (between the eye and `bodyM` below it), so the walls
// of another level do not.
import { pointInPolygon, sceneBounds } from "./plan_math.js";

export const bodyRadiusM = 0.2;
export const bodyM = 1.3;
const substepM = 0.02;  // a step is checked every 2 cm: thinner than any wall with the body around it

const validRoom = (room) => Array.isArray(room?.points) && room.points.length >= 3 &&
  room.points.every((q) => Array.isArray(q) && q.length >= 2);

function polygonArea(poly) {
  let a = 0;
  for (let i = 0, j = poly.length - 1; i < poly.length; j = i++) a += poly[j][0] * poly[i][1] - poly[i][0] * poly[j][1];
  return Math.abs(a) / 2;
}

// A point inside `poly`: its vertices' mean when that is inside, else the middle of the widest
// inside run of the horizontal line through it (a concave room).
export function pointInside(poly) {
  const mean = [0, 1].map((k) => poly.reduce((s, q) => s + q[k], 0) / poly.length);
  if (pointInPolygon(mean, poly)) return mean;
  const z = mean[1];
  const xs = [];
  for (let i = 0, j = poly.length - 1; i < poly.length; j = i++) {
    const [a, b] = [poly[j], poly[i]];
    if ((a[1] > z) !== (b[1] > z)) xs.push(a[0] + ((z - a[1]) * (b[0] - a[0])) / (b[1] - a[1]));
  }
  xs.sort((p, q) => p - q);
  let best = null;
  for (let k = 0; k + 1 < xs.length; k += 2) if (!best || xs[k + 1] - xs[k] > best[1] - best[0]) best = [xs[k], xs[k + 1]];
  return best ? [(best[0] + best[1]) / 2, z] : mean;
}

// Where the visitor starts: the eye [x, z] when it is inside a room (an imported observer camera)
// or, in a scene without rooms, inside the walls' bounds; else the room under `planCentre`, else
// the largest room; null when there is nothing to be inside of (the eye stays).
export function visitorStart(scene, eye, planCentre) {
  const rooms = (scene.rooms || []).filter(validRoom).map((r) => r.points.map((q) => [q[0], q[1]]));
  if (!rooms.length) {
    const b = sceneBounds({ walls: scene.walls || [] });
    if (!b) return null;
    const inside = (p) => p[0] > b[0][0] && p[0] < b[1][0] && p[1] > b[0][1] && p[1] < b[1][1];
    if (inside(eye)) return eye;
    return inside(planCentre) ? planCentre : [(b[0][0] + b[1][0]) / 2, (b[0][1] + b[1][1]) / 2];
  }
  if (rooms.some((r) => pointInPolygon(eye, r))) return eye;
  const under = rooms.find((r) => pointInPolygon(planCentre, r));
  if (under) return planCentre;
  const largest = rooms.reduce((a, b) => (polygonArea(b) > polygonArea(a) ? b : a));
  return pointInside(largest);
}

// True when a body at plan point q (eye at height eyeY) overlaps a wall, outside its doors.
export function collides(scene, q, eyeY, radius = bodyRadiusM) {
  for (const w of scene.walls || []) {
    if (!Array.isArray(w.start) || !Array.isArray(w.end)) continue;
    const base = w.base ?? 0;
    if (base > eyeY || base + (w.height ?? 2.5) < eyeY - bodyM) continue;
    const d = [w.end[0] - w.start[0], w.end[1] - w.start[1]];
    const length = Math.hypot(d[0], d[1]);
    if (length < 1e-9) continue;
    const u = [d[0] / length, d[1] / length];
    const rel = [q[0] - w.start[0], q[1] - w.start[1]];
    const along = rel[0] * u[0] + rel[1] * u[1];
    const across = Math.abs(rel[0] * -u[1] + rel[1] * u[0]);
    const reach = (w.thickness ?? 0.15) / 2 + radius;
    // The wall's footprint grown by the body: within `reach` of its centreline, ends rounded.
    const s = Math.max(0, Math.min(length, along));
    if (Math.hypot(w.start[0] + u[0] * s - q[0], w.start[1] + u[1] * s - q[1]) >= reach) continue;
    const inDoor = across < reach && (w.openings || []).some((o) => o?.type === "door" &&
      along >= (o.offset ?? 0) + radius && along <= (o.offset ?? 0) + (o.width ?? 0) - radius &&
      (o.height ?? 2.0) >= Math.min(eyeY - base, bodyM));
    if (!inDoor) return true;
  }
  return false;
}

// The farthest point of the straight step from -> to that the body reaches without entering a
// wall (from itself when it starts inside one, so a visitor placed in a wall can walk out).
export function walkTo(scene, from, to, eyeY, radius = bodyRadiusM) {
  const length = Math.hypot(to[0] - from[0], to[1] - from[1]);
  const n = Math.max(1, Math.ceil(length / substepM));
  const startsInside = collides(scene, from, eyeY, radius);
  let reached = from;
  for (let i = 1; i <= n; i++) {
    const q = [from[0] + ((to[0] - from[0]) * i) / n, from[1] + ((to[1] - from[1]) * i) / n];
    if (collides(scene, q, eyeY, radius) && !startsInside) return reached;
    reached = q;
  }
  return to;
}
