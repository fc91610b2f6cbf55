// As-you-type schema checks with the repository's schemas: every example passes, and each kind of
// mistake gives exactly one message at the pointer of the mistake (not the validator's whole trace).
import { test } from "node:test";
import assert from "node:assert/strict";
import fs from "node:fs";
import { makeRequestChecker } from "../src/schema_check.js";

const root = new URL("../../../", import.meta.url);
const readJson = (path) => JSON.parse(fs.readFileSync(new URL(path, root), "utf8"));
const check = makeRequestChecker(readJson("schemas/request.schema.json"), readJson("schemas/scene.schema.json"));
const tetrahedron = () => readJson("examples/tetrahedron.json");

test("every example passes", () => {
  for (const name of fs.readdirSync(new URL("examples/", root)).filter((n) => n.endsWith(".json"))) {
    assert.deepEqual(check(readJson(`examples/${name}`)), [], name);
  }
});

test("one message per mistake, at its pointer", () => {
  const request = tetrahedron();
  request.camera.fov_y = 500;
  request.options.bogus = 1;
  request.scene.solids[0].faces = 3;
  request.scene.solids.push({ type: "box", center: [0, 0], size: [1, -1, 1] });
  const pointers = check(request).map((d) => d.pointer).sort();
  assert.deepEqual(pointers, ["/camera/fov_y", "/options/bogus", "/scene/solids/0/faces", "/scene/solids/1/size/1"]);
  const byPointer = Object.fromEntries(check(request).map((d) => [d.pointer, d.message]));
  assert.match(byPointer["/camera/fov_y"], /170/);
  assert.match(byPointer["/options/bogus"], /unknown member "bogus"/);
  assert.match(byPointer["/scene/solids/0/faces"], /array/);
});

test("an unknown solid type names the types there are", () => {
  const request = tetrahedron();
  request.scene.solids = [{ type: "sphere", radius: 1 }];
  const errors = check(request);
  assert.equal(errors.length, 1, JSON.stringify(errors));
  assert.equal(errors[0].pointer, "/scene/solids/0/type");
  for (const t of ["box", "cylinder", "pyramid", "prism", "mesh"]) assert.match(errors[0].message, new RegExp(`"${t}"`));
});

test("a colour in the wrong form is reported once, by the branch of its own JSON type", () => {
  const request = tetrahedron();
  request.scene.background = "red";
  const errors = check(request);
  assert.equal(errors.length, 1, JSON.stringify(errors));
  assert.equal(errors[0].pointer, "/scene/background");
});

test("a missing required member points at its object", () => {
  const request = tetrahedron();
  delete request.scene.solids[0].vertices;
  const errors = check(request);
  assert.deepEqual(errors.map((d) => [d.pointer, d.message]), [["/scene/solids/0", 'needs "vertices"']]);
});
