// Pointer ranges and pointer edits on real request text (examples/studio.json and small fixtures):
// the range must cover exactly the offending value, and an edit must change only what it names.
import { test } from "node:test";
import assert from "node:assert/strict";
import fs from "node:fs";
import { parseTree, pointerRange, pointerAt, setAtPointer, applyChange, parsePointer, formatPointer, formatValue }
  from "../src/json_pointer.js";

const studio = fs.readFileSync(new URL("../../../examples/studio.json", import.meta.url), "utf8");
const slice = (text, r) => text.slice(r.from, r.to);
const range = (text, p) => pointerRange(text, parseTree(text), p);
const set = (text, p, v) => {
  const change = setAtPointer(text, parseTree(text), p, v);
  return change && applyChange(text, change);
};

test("pointer tokens follow RFC 6901 escaping", () => {
  assert.deepEqual(parsePointer("/a~1b/c~0d/0"), ["a/b", "c~d", "0"]);
  assert.deepEqual(parsePointer(""), []);
  assert.equal(formatPointer(["a/b", "c~d", 0]), "/a~1b/c~0d/0");
  assert.throws(() => parsePointer("a"));
});

test("a scalar's range is its own text", () => {
  const r = range(studio, "/camera/fov_y");
  assert.equal(r.exact, true);
  assert.equal(Number(slice(studio, r)), JSON.parse(studio).camera.fov_y);
  assert.equal(slice(studio, range(studio, "/scene/walls/0/openings/0/type")), '"window"');
  assert.equal(slice(studio, range(studio, "/scene/floor/cells/1")), "9");
});

test("an object or array is marked by its key, the root by its brace", () => {
  assert.equal(slice(studio, range(studio, "/scene/walls")), '"walls"');
  assert.equal(slice(studio, range(studio, "/camera")), '"camera"');
  assert.equal(slice(studio, range(studio, "")), "{");
  const anonymous = range(studio, "/scene/walls/1");
  assert.equal(slice(studio, anonymous), "{");
  assert.ok(studio.slice(anonymous.from).startsWith('{\n        "id": "east"'));
});

test("the value range covers the whole value, also where the mark is only its key", () => {
  const r = range(studio, "/camera");
  assert.deepEqual(JSON.parse(studio.slice(r.value.from, r.value.to)), JSON.parse(studio).camera);
  const v = range(studio, "/camera/fov_y");
  assert.deepEqual([v.value.from, v.value.to], [v.from, v.to]);
});

test("a missing member marks the deepest part that exists", () => {
  const r = range(studio, "/camera/no_such_key");
  assert.equal(r.exact, false);
  assert.equal(slice(studio, r), '"camera"');
  assert.equal(range(studio, "/scene/walls/99").exact, false);
});

test("keys with escapes and a broken document still resolve", () => {
  const text = '{"a/b": {"c~d": [10, 20]}, "broken": , "after": 3}';
  assert.equal(slice(text, range(text, "/a~1b/c~0d/1")), "20");
  assert.equal(slice(text, range(text, "/after")), "3");
  assert.equal(slice(text, range(text, "/broken")), '"broken"');
});

test("pointerAt is the inverse of pointerRange", () => {
  for (const p of ["/camera/position/2", "/scene/walls/3/color", "/scene/floor/colors/1", "/options/width"]) {
    const r = range(studio, p);
    assert.equal(pointerAt(studio, parseTree(studio), r.from), p);
  }
});

test("setting an existing value replaces only that value", () => {
  const change = setAtPointer(studio, parseTree(studio), "/camera/position", [1, 2, 3.5]);
  assert.equal(studio.slice(change.from, change.to), "[5.3, 1.6, 4]");
  assert.equal(change.insert, "[1, 2, 3.5]");
  const expected = JSON.parse(studio);
  expected.camera.position = [1, 2, 3.5];
  assert.deepEqual(JSON.parse(applyChange(studio, change)), expected);
});

test("setting a missing member inserts it, nested, keeping the document valid", () => {
  const cases = [
    ['{"options": {"width": 64}}', "/options/pipeline", "bsp"],
    ['{"options": {}}', "/options/shadows", true],
    ["{}", "/options/painter/key", "newell"],
    ['{\n  "scene": {}\n}', "/options/shading", "phong"],
    [studio, "/options/shadow/size", 512],
  ];
  for (const [text, pointer, value] of cases) {
    const out = set(text, pointer, value);
    const expected = JSON.parse(text);
    let target = expected;
    const tokens = parsePointer(pointer);
    for (const t of tokens.slice(0, -1)) target = target[t] ??= {};
    target[tokens.at(-1)] = value;
    assert.deepEqual(JSON.parse(out), expected, `${pointer} in ${text.slice(0, 40)}`);
  }
});

test("inserted members follow the surrounding indentation", () => {
  const out = set('{\n  "options": {\n    "width": 64\n  }\n}', "/options/height", 48);
  assert.equal(out, '{\n  "options": {\n    "width": 64,\n    "height": 48\n  }\n}');
});

test("edits that would need guessing are refused", () => {
  assert.equal(set('{"a": [1]}', "/a/5", 2), null);
  assert.equal(set('{"a": 1}', "/a/b", 2), null);
  assert.equal(set("[1, 2]", "/x", 1), null);
});

test("formatValue keeps arrays of scalars on one line", () => {
  assert.equal(formatValue({ a: [1, 2], b: { c: "x" } }),
    '{\n  "a": [1, 2],\n  "b": {\n    "c": "x"\n  }\n}');
});
