// Camera moves for dragging, scrolling and arrow keys on the image. In: a request's camera (world
// space, metres, +Y up, defaults as in docs/scene-format.md) and a gesture in pixels or degrees.
// Out: a new {position, target} with the other members untouched. Orbit turns the eye about the
// target on a sphere (azimuth about +Y, elevation kept within ±89° so the look-at never becomes
// parallel to `up`); pan moves eye and target together in the view plane; zoom scales the distance.
export const cameraDefaults = Object.freeze({
  position: [0, 1.6, 5], target: [0, 1, 0], up: [0, 1, 0], fov_y: 60,
});

const maxElevationDeg = 89;
const minDistance = 0.05;  // metres: closer than the default near plane makes everything vanish
const maxDistance = 1e5;

const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const add = (a, b) => [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
const scale = (a, s) => [a[0] * s, a[1] * s, a[2] * s];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const length = (a) => Math.sqrt(dot(a, a));
const normalize = (a) => scale(a, 1 / (length(a) || 1));
const rad = (deg) => (deg * Math.PI) / 180;

// Editor-friendly numbers: millimetres are plenty for a camera, and "1.6" reads better than
// "1.6000000000000003".
export function roundVec(v, digits = 3) {
  const f = 10 ** digits;
  return v.map((x) => Math.round(x * f) / f + 0);  // + 0 turns -0 into 0
}

export function withDefaults(camera) {
  return { ...cameraDefaults, ...(camera || {}) };
}

// Offset of the eye from the target as (distance, azimuth, elevation) in degrees; azimuth 0 is +Z.
export function toSpherical(position, target) {
  const d = sub(position, target);
  const r = length(d);
  return {
    distance: r,
    azimuth: (Math.atan2(d[0], d[2]) * 180) / Math.PI,
    elevation: r > 0 ? (Math.asin(Math.max(-1, Math.min(1, d[1] / r))) * 180) / Math.PI : 0,
  };
}

export function fromSpherical(target, { distance, azimuth, elevation }) {
  const a = rad(azimuth);
  const e = rad(elevation);
  return add(target, [distance * Math.cos(e) * Math.sin(a), distance * Math.sin(e), distance * Math.cos(e) * Math.cos(a)]);
}

// Dragging right turns the scene right, as a turntable: the eye moves the other way round.
export function orbit(camera, dAzimuthDeg, dElevationDeg) {
  const c = withDefaults(camera);
  const s = toSpherical(c.position, c.target);
  if (s.distance === 0) return { position: c.position, target: c.target };
  const elevation = Math.max(-maxElevationDeg, Math.min(maxElevationDeg, s.elevation + dElevationDeg));
  const position = fromSpherical(c.target, { ...s, azimuth: s.azimuth - dAzimuthDeg, elevation });
  return { position: roundVec(position), target: c.target };
}

// Moves eye and target so the point under the cursor follows it: `dxPx`, `dyPx` are the drag in
// pixels of an image `heightPx` tall (the vertical field of view spans it at the target's distance).
export function pan(camera, dxPx, dyPx, heightPx) {
  const c = withDefaults(camera);
  const forward = sub(c.target, c.position);
  const distance = length(forward);
  if (distance === 0 || heightPx <= 0) return { position: c.position, target: c.target };
  const right = normalize(cross(forward, c.up));
  const up = normalize(cross(right, forward));
  const metresPerPixel = (2 * distance * Math.tan(rad(c.fov_y) / 2)) / heightPx;
  const move = add(scale(right, -dxPx * metresPerPixel), scale(up, dyPx * metresPerPixel));
  return { position: roundVec(add(c.position, move)), target: roundVec(add(c.target, move)) };
}

// factor < 1 moves closer. The target stays; the distance stays within sane bounds.
export function zoom(camera, factor) {
  const c = withDefaults(camera);
  const s = toSpherical(c.position, c.target);
  if (s.distance === 0) return { position: c.position, target: c.target };
  const distance = Math.max(minDistance, Math.min(maxDistance, s.distance * factor));
  return { position: roundVec(add(c.target, scale(sub(c.position, c.target), distance / s.distance))), target: c.target };
}

// One wheel notch (deltaY 100 in pixel mode) zooms by 10 %.
export function wheelFactor(deltaY) {
  return Math.exp(Math.max(-500, Math.min(500, deltaY)) * 0.001);
}

// Walk mode's look-around: the target turns about the eye (the eye stays), keeping its distance.
// Dragging right turns the view right.
export function look(camera, dAzimuthDeg, dElevationDeg) {
  const c = withDefaults(camera);
  const s = toSpherical(c.target, c.position);
  if (s.distance === 0) return { position: c.position, target: c.target };
  const elevation = Math.max(-maxElevationDeg, Math.min(maxElevationDeg, s.elevation - dElevationDeg));
  const target = fromSpherical(c.position, { ...s, azimuth: s.azimuth - dAzimuthDeg, elevation });
  return { position: c.position, target: roundVec(target) };
}

// Walk mode starts at eye height `eyeY`: the eye moves up or down, the target by as much, with the
// view's pitch limited so the walker looks ahead rather than at the floor.
export function atEyeHeight(camera, eyeY, maxPitch = 0.3) {
  const c = withDefaults(camera);
  const dy = eyeY - c.position[1];
  const target = [c.target[0], c.target[1] + dy, c.target[2]];
  const h = Math.hypot(target[0] - c.position[0], target[2] - c.position[2]);
  if (h > 1e-6) target[1] = eyeY + Math.max(-maxPitch, Math.min(maxPitch, (target[1] - eyeY) / h)) * h;
  return { position: roundVec([c.position[0], eyeY, c.position[2]]), target: roundVec(target) };
}

// One walk step of `metres`: forward (+1/−1) along the view's direction in plan, right (+1/−1)
// across it; eye and target move together and keep their heights.
export function walkStep(camera, forward, right, metres) {
  const c = withDefaults(camera);
  const f = [c.target[0] - c.position[0], c.target[2] - c.position[2]];
  const len = Math.hypot(f[0], f[1]);
  if (len < 1e-9) return { position: c.position, target: c.target };
  const [fx, fz] = [f[0] / len, f[1] / len];
  const [rx, rz] = [-fz, fx];  // right of the view direction, +Y up
  const move = [(fx * forward + rx * right) * metres, 0, (fz * forward + rz * right) * metres];
  return { position: roundVec(add(c.position, move)), target: roundVec(add(c.target, move)) };
}

// A camera over plan bounds [[minX, minZ], [maxX, maxZ]]: looking at their centre 1 m up, 55° down
// from the +Z side, far enough for a vertical field of view `fovDeg` to hold their diagonal.
export function frameBounds([lo, hi], fovDeg = cameraDefaults.fov_y) {
  const centre = [(lo[0] + hi[0]) / 2, 1, (lo[1] + hi[1]) / 2];
  const radius = Math.max(1, Math.hypot(hi[0] - lo[0], hi[1] - lo[1]) / 2);
  const d = (radius / Math.tan(rad(fovDeg) / 2)) * 1.1;
  const e = rad(55);
  return { position: roundVec(add(centre, [0, d * Math.sin(e), d * Math.cos(e)])), target: roundVec(centre) };
}

// The ray through point (u, v) of a width x height image (pixels from its top-left corner; a pixel's
// centre is at +0.5), as the server's look-at and perspective projection draw it: {origin, dir},
// dir of unit length.
export function pixelRay(camera, width, height, u, v) {
  const c = withDefaults(camera);
  const forward = normalize(sub(c.target, c.position));
  const right = normalize(cross(forward, c.up || [0, 1, 0]));
  const up = cross(right, forward);
  const tanY = Math.tan(rad(c.fov_y) / 2);
  const x = ((u / width) * 2 - 1) * tanY * (width / height);
  const y = (1 - (v / height) * 2) * tanY;
  return { origin: c.position, dir: normalize(add(forward, add(scale(right, x), scale(up, y)))) };
}

// Where a ray meets the horizontal plane at height `y`: [x, z] in plan, or null when it runs
// parallel to it or meets it behind the eye.
export function rayAtHeight({ origin, dir }, y) {
  if (Math.abs(dir[1]) < 1e-9) return null;
  const t = (y - origin[1]) / dir[1];
  return t > 0 ? [origin[0] + dir[0] * t, origin[2] + dir[2] * t] : null;
}
