import { test } from "node:test";
import assert from "node:assert/strict";
import { missingModelsHint } from "../src/import_hint.js";

const warning = (n) => `${n} furniture models were not found and 0 could not be read: those pieces are boxes (not found: a.obj)`;

test("a bare Home.xml whose models are missing gets the hint with both ways to the models", () => {
  const hint = missingModelsHint("Studio.xml", ["the home has no observer camera", warning(28)]);
  assert.match(hint, /^Studio\.xml came without its furniture models \(28 furniture models not found\), so those pieces are drawn as boxes/);
  assert.match(hint, /open the \.sh3d file/);
  assert.match(hint, /zip Home\.xml together with its furniture\/ folder/);
});

test("one missing model is said in the singular", () => {
  assert.match(missingModelsHint("Home.xml", [warning(1)]), /\(1 furniture model not found\)/);
  assert.match(missingModelsHint("Home.zip", [warning(1)]), /^1 furniture model named by the home is not in Home\.zip, so the pieces using it/);
});

test("a zip that still lacks models is told to carry the whole folder", () => {
  assert.match(missingModelsHint("Home.zip", [warning(2)]), /Zip the home with its whole furniture\/ folder/);
});

test("no hint when every model was found, or only unreadable ones", () => {
  assert.equal(missingModelsHint("Home.xml", []), null);
  assert.equal(missingModelsHint("Home.xml", undefined), null);
  assert.equal(missingModelsHint("Home.xml", ["0 furniture models were not found and 2 could not be read: those pieces are boxes"]), null);
});
