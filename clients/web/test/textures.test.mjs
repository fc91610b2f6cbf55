// The texture palette's pure logic (textures.js): palette entries from the catalogue's answer and
// from an upload, which side of a wall a plan point is on, and which surface a click paints.
import { test } from "node:test";
import assert from "node:assert/strict";
import { paletteEntries, uploadedEntry, textureOf, wallSide, paintTarget, wallSideStrip, storedImageId } from "../src/textures.js";

const answer = {
  textures: [
    { id: "00112233445566aa", catalog_id: "eTeks#woodenFloor", name: "Wooden floor", category: "Floor", size_cm: { width: 42.5, height: 42.5 }, url: "/v1/textures/00112233445566aa" },
    { id: "00112233445566bb", catalog_id: "eTeks#blueSky", name: "Blue sky", category: "Sky", size_cm: { width: 100, height: 41.3 }, url: "/v1/textures/00112233445566bb" },
    { id: "00112233445566cc", catalog_id: "eTeks#smallBricks", name: "Small bricks", category: "Wall", size_cm: { width: 23, height: 14.9 }, url: "/v1/textures/00112233445566cc" },
  ],
};

test("the palette keeps the catalogue's order, leaves out the skies and gives tile sizes in metres", () => {
  const entries = paletteEntries(answer);
  assert.deepEqual(entries.map((e) => e.name), ["Wooden floor", "Small bricks"]);
  assert.equal(entries[0].widthM, 0.425);
  assert.deepEqual(textureOf(entries[1]), { image: "00112233445566cc", width: 0.23, height: 0.149 });
  assert.deepEqual(paletteEntries(null), []);
});

test("an uploaded image is a 1 m tile in its own proportions, named by its stored id", () => {
  const e = uploadedEntry({ id: "0123456789abcdef", width: 200, height: 100 }, "photo.png");
  assert.deepEqual(textureOf(e), { image: "0123456789abcdef", width: 1, height: 0.5 });
  assert.equal(e.url, "/v1/textures/0123456789abcdef");
});

test("the left side of a wall faces (dz, -dx)", () => {
  const wall = { start: [0, 0], end: [4, 0] };  // along +x: left faces (0, -4), toward -z
  assert.equal(wallSide(wall, [2, -0.05]), "left");
  assert.equal(wallSide(wall, [2, 0.05]), "right");
  const strip = wallSideStrip({ ...wall, thickness: 0.2 }, "left");
  assert.deepEqual(strip, [[0, 0], [4, 0], [4, -0.1], [0, -0.1]]);
});

test("a click paints a wall side, then a solid, then a room's floor, then the floor grid", () => {
  const scene = {
    walls: [{ start: [0, 0], end: [4, 0], thickness: 0.2, openings: [{ type: "door", offset: 1, width: 0.9 }] }],
    solids: [{ type: "box", center: [2, 2], size: [0.5, 0.5, 0.5] }],
    rooms: [{ points: [[0, 0], [4, 0], [4, 3], [0, 3]] }],
    floor: { cells: [10, 10], cell_size: 1, origin: [-3, -3] },
  };
  assert.deepEqual(paintTarget(scene, [3, 0.05], 0.1), { pointer: "/scene/walls/0", member: "right_texture" });
  assert.deepEqual(paintTarget(scene, [1.2, -0.05], 0.1), { pointer: "/scene/walls/0", member: "left_texture" }, "through a door: its wall");
  assert.deepEqual(paintTarget(scene, [2.1, 2.1], 0.1), { pointer: "/scene/solids/0", member: "texture" });
  assert.deepEqual(paintTarget(scene, [1, 2], 0.1), { pointer: "/scene/rooms/0", member: "floor_texture" });
  assert.deepEqual(paintTarget(scene, [5, 5], 0.1), { pointer: "/scene/floor", member: "texture" });
  assert.equal(paintTarget(scene, [9, 9], 0.1), null);
});

test("only a 16-hex image is a stored image's id", () => {
  assert.equal(storedImageId({ image: "0123456789abcdef" }), "0123456789abcdef");
  assert.equal(storedImageId({ image: "data:image/png;base64,AAAA" }), null);
  assert.equal(storedImageId(undefined), null);
});
