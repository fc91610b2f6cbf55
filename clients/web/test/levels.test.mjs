// The level tabs' rules (levels.js) on the levels of Sweet Home 3D's 3BedroomHouseWithAttic as
// imported: two viewable storeys, then an attic and a roof at the same elevation, not viewable.
import { test } from "node:test";
import assert from "node:assert/strict";
import { sceneLevels, levelsToDraw, levelShown, onLevel, levelLabel } from "../src/levels.js";

const scene = {
  levels: [
    { id: "roof", elevation: 5.24, viewable: false },
    { id: "ground", elevation: 0 },
    { id: "attic", elevation: 5.24, viewable: false },
    { id: "upstairs", elevation: 2.62 },
  ],
};

test("levels are ordered by elevation, then as the scene lists them", () => {
  assert.deepEqual(sceneLevels(scene).map((l) => l.id), ["ground", "upstairs", "roof", "attic"]);
  assert.deepEqual(sceneLevels({}), []);
  assert.equal(levelLabel(scene.levels[3]), "upstairs · 2.62 m");
});

test("a tab draws its level and those before it; All draws the viewable ones", () => {
  assert.deepEqual(levelsToDraw(scene, "ground"), ["ground"]);
  assert.deepEqual(levelsToDraw(scene, "upstairs"), ["ground", "upstairs"]);
  assert.deepEqual(levelsToDraw(scene, "roof"), ["ground", "upstairs", "roof"]);
  assert.deepEqual(levelsToDraw(scene, null), ["ground", "upstairs"]);
  assert.deepEqual(levelsToDraw(scene, "cellar"), ["ground", "upstairs"]);
});

test("the tab a request shows is the highest level it draws, or All", () => {
  assert.equal(levelShown({ scene }), null);
  assert.equal(levelShown({ scene, options: { levels: ["ground"] } }), "ground");
  assert.equal(levelShown({ scene, options: { levels: ["upstairs", "ground"] } }), null);  // the viewable ones
  assert.equal(levelShown({ scene, options: { levels: ["ground", "attic"] } }), "attic");
});

test("the plan shows a level's elements and those on no level", () => {
  assert.ok(onLevel({ level: "ground" }, "ground"));
  assert.ok(!onLevel({ level: "upstairs" }, "ground"));
  assert.ok(onLevel({}, "ground"));
  assert.ok(onLevel({ level: "upstairs" }, null));
});
