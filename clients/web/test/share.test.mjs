// Links to stored scenes and scenes kept partly out of the editor: the permalink's view round-trips
// exactly, the image URL spells each member as docs/api.md's query parameters do, and a big scene's
// meshes come back whole after being kept out.
import { test } from "node:test";
import assert from "node:assert/strict";
import { viewOf, permalink, parsePermalink, imageUrl } from "../src/share.js";
import { splitMeshes, joinMeshes, isStoredMesh, summarize } from "../src/big_scene.js";

const request = {
  scene: { walls: [] },
  camera: { position: [1.25, 1.6, -0.1], target: [3, 1, 2], fov_y: 55, near: 1e-7 },
  options: { width: 640, height: 480, pipeline: "bsp", shadows: true, bsp: { w1: 8 }, shadow: { fit: "scene", method: "rays" }, extra: 1 },
};

test("a permalink carries the camera and options exactly", () => {
  const link = permalink("http://h:1", "0123456789abcdef", viewOf(request));
  const back = parsePermalink(new URL(link).search);
  assert.equal(back.id, "0123456789abcdef");
  assert.deepEqual(back.view, { camera: request.camera, options: request.options });
  assert.equal(parsePermalink("?example=apartment"), null);
  assert.throws(() => parsePermalink("?scene=ab&view=%5B1%5D"), /not a JSON object/);
  assert.throws(() => parsePermalink("?scene=ab&view=%7B"), /not JSON/);
});

test("the image URL names each member by its query parameter, in plain decimals", () => {
  const { url, missing } = imageUrl("http://h:1", "0123456789abcdef", viewOf(request));
  assert.equal(url, "http://h:1/v1/scenes/0123456789abcdef/render.png?position=1.25,1.6,-0.1&target=3,1,2" +
    "&fov_y=55&near=0.0000001&width=640&height=480&pipeline=bsp&shadows=true&bsp_w1=8&shadow_fit=scene&shadow_method=rays");
  assert.deepEqual(missing, ["/options/extra"]);
});

test("a big scene's meshes are kept out and put back whole", () => {
  const vertices = Array.from({ length: 100 }, (_, i) => [i, i % 7, 0 - i]);
  const faces = Array.from({ length: 98 }, (_, i) => [i, i + 1, i + 2]);
  const scene = { walls: [{ start: [0, 0], end: [1, 0] }], lights: [],
    solids: [{ type: "box", center: [0, 0], size: [1, 1, 1] }, { type: "mesh", id: "m", position: [1, 0, 2], vertices, faces }] };
  const split = splitMeshes(scene);
  const stub = split.scene.solids[1];
  assert.ok(isStoredMesh(stub) && !isStoredMesh(split.scene.solids[0]));
  assert.equal(stub.faces, undefined);
  assert.equal(stub.vertices.length, 8, "the bounding box stands in for the vertices");
  assert.deepEqual(stub.vertices[0], [0, 0, -99]);
  assert.deepEqual(stub.vertices[7], [99, 6, 0]);
  assert.deepEqual(joinMeshes(split.scene, split.meshes), scene);
  // Edits to the rest survive, and a moved mesh keeps its new position.
  const edited = structuredClone(split.scene);
  edited.solids[1].position = [2, 0, 2];
  edited.lights.push({ type: "point", position: [0, 2, 0] });
  const joined = joinMeshes(edited, split.meshes);
  assert.deepEqual(joined.solids[1], { ...scene.solids[1], position: [2, 0, 2] });
  assert.equal(joined.lights.length, 1);
  assert.match(summarize(split.scene, 2.5e6, split.meshes.size), /^2\.50 MB scene: 1 walls, 2 solids \(1 meshes kept out/);
});

test("a big scene's pieces keep their placement in the editor; their parts' meshes come back whole", () => {
  const vertices = Array.from({ length: 100 }, (_, i) => [i / 100 - 0.5, 0, 0]);
  const faces = Array.from({ length: 98 }, (_, i) => [i, i + 1, i + 2]);
  const piece = { type: "piece", id: "sofa", center: [1, 2], size: [2, 1, 1],
    parts: [{ name: "frame", ref: "0123456789abcdef" }, { name: "cushion", vertices, faces, color: [1, 0, 0] }] };
  const scene = { solids: [piece] };
  const split = splitMeshes(scene);
  const stub = split.scene.solids[0];
  assert.ok(isStoredMesh(stub));
  assert.deepEqual(stub.parts[0], piece.parts[0], "a part placed by ref is small: it stays");
  assert.equal(stub.parts[1].faces, undefined);
  assert.equal(stub.parts[1].name, "cushion");
  assert.deepEqual(stub.center, [1, 2]);
  const moved = structuredClone(split.scene);
  moved.solids[0].center = [3, 2];
  assert.deepEqual(joinMeshes(moved, split.meshes).solids[0], { ...piece, center: [3, 2] });
});

test("the browser's copy of a big scene opens as a permalink", async () => {
  const { storedSceneLink } = await import("../src/sharing.js");
  const view = viewOf(request);
  const link = storedSceneLink(JSON.stringify({ stored_scene: "0123456789abcdef", view }));
  assert.deepEqual(parsePermalink(link), { id: "0123456789abcdef", view });
  assert.equal(storedSceneLink('{"scene": {}}'), null, "a request is no link");
  assert.equal(storedSceneLink(null), null);
});
