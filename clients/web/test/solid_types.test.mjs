// The page's table of solid types against schemas/scene.schema.json, as unit.SchemaTables holds the
// renderer's: one row per type of the schema's "solid", in its order, and every field of a row's
// panel names a member that type has.
import { test } from "node:test";
import assert from "node:assert/strict";
import fs from "node:fs";
import { solidTypes } from "../src/solid_types.js";

const scene = JSON.parse(fs.readFileSync(new URL("../../../schemas/scene.schema.json", import.meta.url), "utf8"));
const def = (ref) => scene.$defs[ref.replace("#/$defs/", "")];
const schemaTypes = scene.$defs.solid.oneOf.map((branch) => def(branch.$ref).properties.type.const);

test("one row per solid type of the schema, in its order", () => {
  assert.deepEqual(Object.keys(solidTypes), schemaTypes);
});

test("every field of a type's panel is a member of that type", () => {
  const samples = {
    box: { type: "box", center: [1, 2], size: [1, 1, 1] },
    cylinder: { type: "cylinder", center: [1, 2], radius: 0.5, height: 1 },
    pyramid: { type: "pyramid", center: [1, 2], size: [1, 1, 1] },
    prism: { type: "prism", points: [[0, 0], [1, 0], [0, 1]], height: 1 },
    mesh: { type: "mesh", vertices: [[0, 0, 0], [1, 0, 0], [0, 0, 1]], faces: [[0, 1, 2]] },
    piece: { type: "piece", center: [1, 2], size: [1, 1, 1], parts: [{ ref: "0123456789abcdef" }] },
  };
  for (const [type, row] of Object.entries(solidTypes)) {
    const members = def(`#/$defs/${type}`).properties;
    for (const field of row.fields(samples[type])) assert.ok(members[field.path[0]], `${type}: ${field.path.join("/")}`);
  }
});
