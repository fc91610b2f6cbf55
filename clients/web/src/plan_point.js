// Points of the plan, [x, z] in metres: rounding to the millimetre, and an object-space point turned by
// rotation_y and placed. rotation_y turns counter-clockwise seen from above (+X toward −Z), as the
// format says. Pure functions; no DOM.

export const mm = (v) => Math.round(v * 1000) / 1000 + 0;
export const roundPoint = (p) => [mm(p[0]), mm(p[1])];

// Object space (x, z) turned by rotation_y degrees, then moved to `center`.
export function placePoint([x, z], rotationDeg, center) {
  const r = (rotationDeg * Math.PI) / 180;
  const c = Math.cos(r);
  const s = Math.sin(r);
  return [center[0] + x * c + z * s, center[1] - x * s + z * c];
}
