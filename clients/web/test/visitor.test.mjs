// The visitor's walls: a step into a wall stops with the body's radius to spare, a step through a
// door opening passes, a window or a wall of another level does not change that, and the start is
// inside (the eye when it is in a room, else the room under the plan's centre, else the largest).
import { test } from "node:test";
import assert from "node:assert/strict";
import { walkTo, collides, visitorStart, pointInside, bodyRadiusM } from "../src/visitor.js";
import { pointInPolygon } from "../src/plan_math.js";

// A wall along x = 2 from z = 0 to z = 4, 0.2 m thick, a 0.9 m door at z 1..1.9 and a window at z 3..3.5.
const wall = { start: [2, 0], end: [2, 4], thickness: 0.2, height: 2.5,
  openings: [{ type: "door", offset: 1, width: 0.9 }, { type: "window", offset: 3, width: 0.5 }] };
const scene = { walls: [wall] };

test("a step into the wall stops the body's radius before its face", () => {
  const reached = walkTo(scene, [0.5, 2.5], [3.5, 2.5], 1.6);
  assert.ok(reached[0] < 2 - 0.1 - bodyRadiusM + 1e-9, `stopped before the wall: ${reached}`);
  assert.ok(reached[0] > 2 - 0.1 - bodyRadiusM - 0.03, `and close to it: ${reached}`);
  assert.equal(reached[1], 2.5);
});

test("a step through the door passes", () => {
  assert.deepEqual(walkTo(scene, [0.5, 1.45], [3.5, 1.45], 1.6), [3.5, 1.45]);
});

test("a window is no door", () => {
  assert.ok(walkTo(scene, [0.5, 3.25], [3.5, 3.25], 1.6)[0] < 2);
});

test("a door narrower than the body stops it", () => {
  const narrow = { walls: [{ ...wall, openings: [{ type: "door", offset: 1, width: 0.3 }] }] };
  assert.ok(walkTo(narrow, [0.5, 1.15], [3.5, 1.15], 1.6)[0] < 2);
});

test("a wall of the level above does not stop the visitor", () => {
  const upstairs = { walls: [{ ...wall, base: 2.8, openings: [] }] };
  assert.equal(collides(upstairs, [2, 2.5], 1.6), false);
  assert.deepEqual(walkTo(upstairs, [0.5, 2.5], [3.5, 2.5], 1.6), [3.5, 2.5]);
});

test("a visitor placed in a wall can walk out of it", () => {
  assert.deepEqual(walkTo(scene, [2, 2.5], [0.5, 2.5], 1.6), [0.5, 2.5]);
});

const rooms = [
  { points: [[0, 0], [2, 0], [2, 4], [0, 4]] },
  { points: [[2, 0], [8, 0], [8, 4], [2, 4]] },
];

test("the start: the eye inside a room stays", () => {
  assert.deepEqual(visitorStart({ rooms }, [1, 1], [5, 2]), [1, 1]);
});

test("the start: else the room under the plan's centre, else the largest room", () => {
  assert.deepEqual(visitorStart({ rooms }, [20, 20], [1.5, 2]), [1.5, 2]);
  const start = visitorStart({ rooms }, [20, 20], [30, 30]);
  assert.ok(pointInPolygon(start, rooms[1].points), `inside the largest room: ${start}`);
});

test("a point inside a concave room", () => {
  const ell = [[0, 0], [4, 0], [4, 1], [1, 1], [1, 4], [0, 4]];
  assert.ok(pointInPolygon(pointInside(ell), ell));
});
