// The designer's undo history: designer steps, typing that settles into one step, undo past typing
// that never settled, and camera moves that amend the last step without being one.
import { test } from "node:test";
import assert from "node:assert/strict";
import { History } from "../src/history.js";
import { walkStep, atEyeHeight, frameBounds } from "../src/camera.js";

test("undo and redo walk the recorded steps; a new step drops the redo side", () => {
  const h = new History("a");
  h.record("a", "b");
  h.record("b", "c");
  assert.equal(h.back("c"), "b");
  assert.equal(h.back("b"), "a");
  assert.equal(h.back("a"), null);
  assert.equal(h.forward("a"), "b");
  h.record("b", "d");
  assert.equal(h.forward("d"), null);
  assert.equal(h.back("d"), "b");
});

test("typing settles into one step only when it parses and differs", () => {
  const h = new History("{}");
  h.settle("{", false);
  assert.equal(h.undo.length, 0);
  h.settle('{"a":1}', true);
  h.settle('{"a":1}', true);
  assert.deepEqual(h.undo, ["{}"]);
  // Unsettled text is kept for redo.
  assert.equal(h.back('{"a":1'), "{}");
  assert.equal(h.forward("{}"), '{"a":1');
});

test("a camera move amends the last step", () => {
  const h = new History("x");
  h.record("x", "y");
  h.amend("y with camera");
  assert.equal(h.committed, "y with camera");
  assert.equal(h.back("y with camera"), "x");
  assert.equal(h.forward("x"), "y with camera");
});

test("walk steps move eye and target together, level, by the step", () => {
  const c = atEyeHeight({ position: [0, 5, 5], target: [0, 0, 0] }, 1.6);
  assert.equal(c.position[1], 1.6);
  let w = c;
  for (let i = 0; i < 8; i++) w = walkStep(w, 1, 0, 0.25);
  assert.ok(Math.abs(Math.hypot(w.position[0] - c.position[0], w.position[2] - c.position[2]) - 2) < 1e-3);
  assert.ok(Math.abs(w.position[2] - (c.position[2] - 2)) < 1e-3, "forward is toward the target");
  assert.deepEqual(w.target.map((v, i) => Math.round((v - c.target[i]) * 1000) / 1000), w.position.map((v, i) => Math.round((v - c.position[i]) * 1000) / 1000));
  const r = walkStep({ position: [0, 1.6, 0], target: [0, 1.6, -1] }, 0, 1, 1);
  assert.deepEqual(r.position, [1, 1.6, 0], "looking toward −Z, right is +X");
});

test("framing looks at the centre of the bounds from above the +Z side", () => {
  const f = frameBounds([[0, 0], [5, 4]], 60);
  assert.deepEqual(f.target, [2.5, 1, 2]);
  assert.ok(f.position[1] > 3 && f.position[2] > 4 && f.position[0] === 2.5);
});
