// The designer's plan geometry: snapping, hit tests, opening checks and the catalogue's pieces, on
// hand-placed fixtures (a 5 m × 4 m room) whose answers can be worked out on paper.
import { test } from "node:test";
import assert from "node:assert/strict";
import { snapWallPoint, hitTest, openingProblem, openingAt, placePoint, solidFootprint, moveSolid, sceneBounds, resizeHandles, resizeSolid } from "../src/plan_math.js";
import { makeFurniture, primitiveItems, catalogueEntries, categories } from "../src/catalogue.js";
import { look } from "../src/camera.js";

const walls = [
  { start: [0, 0], end: [5, 0], thickness: 0.15, height: 2.5, openings: [{ type: "door", offset: 1, width: 0.9 }] },
  { start: [5, 0], end: [5, 4], thickness: 0.15, height: 2.5 },
];

test("wall points snap to ends, then to 15° steps and 10 cm lengths, then to the grid", () => {
  assert.deepEqual(snapWallPoint([5.04, 0.03], null, [[5, 0]], 0.1), [5, 0]);
  assert.deepEqual(snapWallPoint([1.23, 0.07], [0, 0], [], 0.1), [1.2, 0]);
  const p = snapWallPoint([2.1, 2.0], [0, 0], [], 0.1);  // 43.6° -> 45°, length 2.9
  assert.ok(Math.abs(p[0] - 2.051) < 1e-3 && Math.abs(p[1] - 2.051) < 1e-3, String(p));
  assert.deepEqual(snapWallPoint([0.26, 0.34], null, [], 0.1), [0.3, 0.3]);
});

test("rotation_y turns +X toward -Z (counter-clockwise from above)", () => {
  const [x, z] = placePoint([1, 0], 90, [0, 0]);
  assert.ok(Math.abs(x) < 1e-12 && Math.abs(z + 1) < 1e-12);
});

test("hit tests find openings before their wall, solids inside their footprint", () => {
  const scene = { walls, solids: [{ type: "box", center: [2, 2], size: [1, 1, 1] }] };
  assert.equal(hitTest(scene, [1.4, 0.02], 0.05), "/scene/walls/0/openings/0");
  assert.equal(hitTest(scene, [3, -0.05], 0.05), "/scene/walls/0");
  assert.equal(hitTest(scene, [2.4, 2.4], 0.05), "/scene/solids/0");
  assert.equal(hitTest(scene, [3.5, 3], 0.05), null);
});

test("an opening that does not fit is refused with the format's rule", () => {
  assert.equal(openingProblem(walls[1], { type: "window", offset: 1, width: 1.2 }), null);
  assert.match(openingProblem(walls[0], { type: "window", offset: 1.5, width: 1 }), /overlap/);
  assert.match(openingProblem(walls[1], { type: "door", offset: 0, width: 6 }), /does not fit/);
  assert.match(openingProblem(walls[1], { type: "window", offset: 0, width: 1, sill: 2, height: 1 }), /above the wall/);
  assert.deepEqual(openingAt(walls[1], 3.9, { type: "window", width: 1.2 }).offset, 2.8);  // slid inside
});

// A catalogue answer as GET /v1/catalogue gives it: two entries, the second standing 1.7 m up.
const answer = { items: [
  { id: "chair", name: "Chair", category: "Living room", size_cm: { width: 40, depth: 42, height: 90 }, icon: "/i/chair.png",
    piece: { type: "piece", size: [0.4, 0.9, 0.42], base: 0, parts: [{ name: "wood", ref: "0123456789abcdef", color: [0.5, 0.3, 0] }] } },
  { id: "pendant_lamp", name: "Pendant lamp", category: "Lights", size_cm: { width: 60, depth: 60, height: 80 }, icon: "/i/l.png",
    piece: { type: "piece", size: [0.6, 0.8, 0.6], base: 1.7, parts: [{ ref: "fedcba9876543210" }] } },
] };

test("every furniture item is a solid whose footprint is centred where it was dropped", () => {
  const entries = catalogueEntries(answer);
  assert.deepEqual(categories(entries), ["Living room", "Lights"]);
  for (const item of [...primitiveItems, ...entries.keys()]) {
    const s = makeFurniture(item, [2, 3], `${item}-1`, entries);
    const f = solidFootprint(s);
    const c = f.circle ? f.circle.center : [0, 1].map((k) => (Math.min(...f.polygon.map((p) => p[k])) + Math.max(...f.polygon.map((p) => p[k]))) / 2);
    assert.ok(Math.abs(c[0] - 2) < 1e-9 && Math.abs(c[1] - 3) < 1e-9, `${item}: ${c}`);
    const moved = moveSolid(s, [3, 3]);
    assert.notEqual(moved, s);
    assert.deepEqual(solidFootprint(moved).circle?.center ?? moved.center, [3, 3]);
  }
  const lamp = makeFurniture("pendant_lamp", [1, 1], "pendant_lamp-1", entries);
  assert.deepEqual(lamp, { type: "piece", id: "pendant_lamp-1", center: [1, 1], rotation_y: 0, size: [0.6, 0.8, 0.6], base: 1.7,
    parts: [{ ref: "fedcba9876543210" }] });
  assert.equal(makeFurniture("sofa", [0, 0], "sofa-1", entries), null, "an item the catalogue does not have");
});

test("a piece's footprint is its box: turned, and the same when mirrored", () => {
  const s = { type: "piece", center: [1, 2], size: [2, 1, 1], rotation_y: 90, parts: [{ ref: "0123456789abcdef" }] };
  const xs = solidFootprint(s).polygon.map((p) => p[0]);
  const zs = solidFootprint(s).polygon.map((p) => p[1]);
  assert.ok(Math.abs(Math.min(...xs) - 0.5) < 1e-9 && Math.abs(Math.max(...xs) - 1.5) < 1e-9, String(xs));
  assert.ok(Math.abs(Math.min(...zs) - 1) < 1e-9 && Math.abs(Math.max(...zs) - 3) < 1e-9, String(zs));
  assert.deepEqual(solidFootprint({ ...s, mirrored: true }), solidFootprint(s));
  assert.equal(hitTest({ solids: [s] }, [1.2, 2.8], 0.01), "/scene/solids/0");
});

test("walk mode's look keeps the eye and the distance to the target", () => {
  const c = { position: [1, 1.6, 1], target: [1, 1.6, -1] };
  const l = look(c, 90, 0);
  assert.deepEqual(l.position, c.position);
  assert.ok(Math.abs(Math.hypot(l.target[0] - 1, l.target[2] - 1) - 2) < 1e-3);
});

test("half-typed elements are skipped, not thrown on", () => {
  const scene = { walls: [{ start: [0, 0] }, ...walls], solids: [{ type: "box", center: [1, 1] }], lights: [{ type: "point" }], floor: {} };
  assert.equal(hitTest(scene, [3, 0], 0.05), "/scene/walls/1");
  assert.deepEqual(sceneBounds(scene), [[0, 0], [5, 4]]);
});

test("a mesh placed by ref stands on its scale box; rooms widen the bounds; nothing is NaN", () => {
  // A stored furniture model is the unit box: scale [2, 1, 0.5] at (3, 1) turned 90° spans x 2.75…3.25, z 0…2.
  const chair = { type: "mesh", ref: "0123456789abcdef", position: [3, 0.5, 1], rotation_y: 90, scale: [2, 1, 0.5] };
  const poly = solidFootprint(chair).polygon;
  const xs = poly.map((q) => q[0]);
  const zs = poly.map((q) => q[1]);
  assert.ok(Math.abs(Math.min(...xs) - 2.75) < 1e-9 && Math.abs(Math.max(...xs) - 3.25) < 1e-9, String(xs));
  assert.ok(Math.abs(Math.min(...zs)) < 1e-9 && Math.abs(Math.max(...zs) - 2) < 1e-9, String(zs));
  assert.ok(hitTest({ walls: [], solids: [chair], lights: [] }, [3, 1.8], 0.05)?.startsWith("/scene/solids/0"));
  // Neither vertices nor ref (half-typed): an empty footprint, not a throw and not ±Infinity bounds.
  assert.deepEqual(solidFootprint({ type: "mesh", position: [1, 0, 1] }).polygon, []);
  const scene = { solids: [{ type: "mesh", position: [1, 0, 1] }], rooms: [{ points: [[-1, -2], [6, -2], [6, 3]] }, { points: "x" }] };
  assert.deepEqual(sceneBounds(scene), [[-1, -2], [6, 3]]);
});

test("a corner handle resizes a box-sized solid, the opposite corner staying where it was", () => {
  const box = { type: "box", center: [0, 0], size: [1, 0.5, 2] };
  assert.deepEqual(resizeHandles(box), [[-0.5, -1], [0.5, -1], [0.5, 1], [-0.5, 1]]);
  const wider = resizeSolid(box, 2, [1, 1.5]);
  assert.deepEqual(wider.size, [1.5, 0.5, 2.5]);
  assert.deepEqual(wider.center, [0.25, 0.25]);
  assert.deepEqual(resizeHandles(wider)[0], [-0.5, -1]);
  // Past the opposite corner: the smallest side, 5 cm.
  assert.deepEqual(resizeSolid(box, 2, [-3, -3]).size, [0.05, 0.5, 0.05]);
  // Keeping proportions: the reach along the diagonal, (1.5·1 + 3·2) / (1² + 2²) = 1.5, scales all three.
  const scaled = resizeSolid(box, 2, [1, 2], true);
  assert.deepEqual(scaled.size, [1.5, 0.75, 3]);
  assert.deepEqual(scaled.center, [0.25, 0.5]);
  // Turned 90°: a pointer moved along +x in the plan lengthens its depth.
  const turned = { type: "piece", center: [2, 3], size: [1, 0.5, 2], rotation_y: 90, parts: [] };
  const deeper = resizeSolid(turned, 2, [3.5, 2.5]);
  assert.deepEqual(deeper.size, [1, 0.5, 2.5]);
  assert.deepEqual(deeper.center, [2.25, 3]);
  const before = resizeHandles(turned)[0];
  const after = resizeHandles(deeper)[0];
  assert.ok(Math.hypot(before[0] - after[0], before[1] - after[1]) < 1e-9, `the opposite corner stays: ${before} ${after}`);
  // A solid not sized by a box has no handles.
  assert.deepEqual(resizeHandles({ type: "cylinder", center: [0, 0], radius: 1, height: 1 }), []);
});
