// Orbit, pan and zoom keep the properties a user relies on: orbit keeps the distance to the target
// and never reaches the pole, pan moves eye and target by the same vector in the view plane, zoom
// keeps the direction, and a full circle of orbit steps comes back to the start.
import { test } from "node:test";
import assert from "node:assert/strict";
import { orbit, pan, zoom, toSpherical, fromSpherical, wheelFactor, pixelRay, rayAtHeight } from "../src/camera.js";

const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
const near = (a, b, eps = 2e-3) => a.every((x, i) => Math.abs(x - b[i]) <= eps);
const camera = { position: [4, 3, 6], target: [1, 1, 1], fov_y: 60 };

test("spherical coordinates round-trip", () => {
  const s = toSpherical(camera.position, camera.target);
  assert.ok(near(fromSpherical(camera.target, s), camera.position, 1e-9));
});

test("orbit keeps the distance and the target", () => {
  const moved = orbit(camera, 37, 12);
  assert.deepEqual(moved.target, camera.target);
  assert.ok(Math.abs(dist(moved.position, moved.target) - dist(camera.position, camera.target)) < 2e-3);
  assert.ok(!near(moved.position, camera.position));
});

test("orbit steps around a full circle return to the start", () => {
  let c = camera;
  for (let i = 0; i < 36; i++) c = { ...c, ...orbit(c, 10, 0) };
  assert.ok(near(c.position, camera.position, 0.02), `${c.position}`);
});

test("orbit elevation stops short of the pole", () => {
  const up = orbit(camera, 0, 500);
  const s = toSpherical(up.position, up.target);
  assert.ok(s.elevation <= 89.01 && s.elevation > 88, `${s.elevation}`);  // 89 deg, then rounded to mm
  const down = orbit(camera, 0, -500);
  assert.ok(toSpherical(down.position, down.target).elevation >= -89.01);
});

test("pan moves eye and target by the same vector, perpendicular to the view", () => {
  const moved = pan(camera, 40, -25, 480);
  const dEye = moved.position.map((x, i) => x - camera.position[i]);
  const dTarget = moved.target.map((x, i) => x - camera.target[i]);
  assert.ok(near(dEye, dTarget));
  const view = camera.target.map((x, i) => x - camera.position[i]);
  const along = dEye.reduce((s, x, i) => s + x * view[i], 0) / Math.hypot(...view);
  assert.ok(Math.abs(along) < 2e-3, `moved ${along} m along the view direction`);
  // Dragging by the image height at the target's distance moves by the visible height there.
  const full = pan(camera, 0, 480, 480);
  const expected = 2 * dist(camera.position, camera.target) * Math.tan(Math.PI / 6);
  assert.ok(Math.abs(dist(full.target, camera.target) - expected) < 5e-3);
});

test("zoom scales the distance and keeps the direction", () => {
  const closer = zoom(camera, 0.5);
  assert.ok(Math.abs(dist(closer.position, camera.target) - dist(camera.position, camera.target) / 2) < 2e-3);
  const s0 = toSpherical(camera.position, camera.target);
  const s1 = toSpherical(closer.position, closer.target);
  assert.ok(Math.abs(s0.azimuth - s1.azimuth) < 0.05 && Math.abs(s0.elevation - s1.elevation) < 0.05);
  assert.ok(dist(zoom(camera, 1e-9).position, camera.target) >= 0.05 - 1e-3);
  assert.ok(wheelFactor(100) > 1 && wheelFactor(-100) < 1 && wheelFactor(0) === 1);
});

test("a camera without position and target uses the documented defaults", () => {
  const moved = orbit({}, 90, 0);
  assert.deepEqual(moved.target, [0, 1, 0]);
  assert.ok(Math.abs(dist(moved.position, [0, 1, 0]) - Math.hypot(0.6, 5)) < 2e-3);
});

// pixelRay is the server's projection run backwards: the image centre looks at the target, the
// image's corners lie at the field of view's edges, and a ray meets a plane where rayAtHeight says.
test("pixelRay follows the look-at projection", () => {
  const c = { position: [4, 3, 6], target: [1, 1, 1], fov_y: 50 };
  const centre = pixelRay(c, 640, 480, 320, 240);
  const toTarget = [c.target[0] - 4, c.target[1] - 3, c.target[2] - 6].map((v) => v / dist(c.target, c.position));
  assert.ok(near(centre.dir, toTarget, 1e-12));
  const top = pixelRay(c, 640, 480, 320, 0);
  const angle = Math.acos(top.dir.reduce((s, v, i) => s + v * centre.dir[i], 0));
  assert.ok(Math.abs(angle - (25 * Math.PI) / 180) < 1e-12, `top edge at half the fov: ${angle}`);
  const corner = pixelRay(c, 640, 480, 640, 0);
  const horizontal = Math.atan(Math.tan((25 * Math.PI) / 180) * (640 / 480));
  const side = pixelRay(c, 640, 480, 640, 240);
  assert.ok(Math.abs(Math.acos(side.dir.reduce((s, v, i) => s + v * centre.dir[i], 0)) - horizontal) < 1e-12);
  assert.ok(corner.dir[1] > side.dir[1], "the top-right corner looks higher than the right edge");
  const floor = rayAtHeight(centre, 1);
  assert.ok(near([floor[0], 1, floor[1]], c.target, 1e-9), `the centre ray meets y = 1 at the target: ${floor}`);
  assert.equal(rayAtHeight(centre, 5), null, "a plane above a downward ray is behind the eye");
});
