// Rooms filled from walls (rooms.js) on hand-placed walls whose inner faces can be worked out on paper.
import { test } from "node:test";
import assert from "node:assert/strict";
import { roomAt, polygonArea, signedArea } from "../src/rooms.js";

const box = (x0, z0, x1, z1, t = 0.2) => [
  { start: [x0, z0], end: [x1, z0], thickness: t }, { start: [x1, z0], end: [x1, z1], thickness: t },
  { start: [x1, z1], end: [x0, z1], thickness: t }, { start: [x0, z1], end: [x0, z0], thickness: t },
];
const sameRing = (a, b) => a.length === b.length && a.some((_, k) => a.every((p, i) => p[0] === b[(i + k) % b.length][0] && p[1] === b[(i + k) % b.length][1]));

test("four walls make a room to their inner faces", () => {
  const room = roomAt(box(0, 0, 5, 4), [2, 2]);
  assert.ok(sameRing(room, [[0.1, 0.1], [4.9, 0.1], [4.9, 3.9], [0.1, 3.9]]), JSON.stringify(room));
  assert.ok(signedArea(room) > 0);
  assert.equal(Math.round(polygonArea(room) * 1e6) / 1e6, 4.8 * 3.8);
  assert.equal(roomAt(box(0, 0, 5, 4), [6, 2]), null, "outside the walls: no room");
  assert.equal(roomAt(box(0, 0, 5, 4).slice(0, 3), [2, 2]), null, "three walls close nothing");
});

test("a wall across a room splits it: the smaller face around the point, each side at its own thickness", () => {
  const walls = [...box(0, 0, 6, 4), { start: [2, 0], end: [2, 4], thickness: 0.1 }];
  // The first wall runs 0..6 in one piece, so (2, 0) is no corner of it: the split is not found.
  assert.ok(sameRing(roomAt(walls, [1, 2]), [[0.1, 0.1], [5.9, 0.1], [5.9, 3.9], [0.1, 3.9]]));
  const split = [
    { start: [0, 0], end: [2, 0], thickness: 0.2 }, { start: [2, 0], end: [6, 0], thickness: 0.2 },
    { start: [6, 0], end: [6, 4], thickness: 0.2 }, { start: [6, 4], end: [2, 4], thickness: 0.2 },
    { start: [2, 4], end: [0, 4], thickness: 0.2 }, { start: [0, 4], end: [0, 0], thickness: 0.2 },
    { start: [2, 0], end: [2, 4], thickness: 0.1 },
  ];
  assert.ok(sameRing(roomAt(split, [1, 2]), [[0.1, 0.1], [1.95, 0.1], [1.95, 3.9], [0.1, 3.9]]), JSON.stringify(roomAt(split, [1, 2])));
  assert.ok(sameRing(roomAt(split, [4, 2]), [[2.05, 0.1], [5.9, 0.1], [5.9, 3.9], [2.05, 3.9]]), JSON.stringify(roomAt(split, [4, 2])));
});
