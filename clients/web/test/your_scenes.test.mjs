import { test } from "node:test";
import assert from "node:assert/strict";
import { formatBytes, listRefusal } from "../src/your_scenes.js";
import { plainWords } from "../src/api.js";

test("sizes are said in B, KB or MB", () => {
  assert.equal(formatBytes(812), "812 B");
  assert.equal(formatBytes(13 * 1024 + 100), "13.1 KB");
  assert.equal(formatBytes(5.65 * 1024 * 1024), "5.7 MB");
  assert.equal(formatBytes(undefined), "");
});

test("a refused list says why and what to do", () => {
  assert.match(listRefusal({ status: 401 }), /access token/);
  assert.match(listRefusal({ status: 403 }), /--allow-listing 1/);
  assert.equal(listRefusal({ status: 500 }), null);
});

test("a full store and a busy server name the serve options an operator raises", () => {
  const full = plainWords({ status: 507, problem: {} });
  assert.match(full, /store is full/);
  assert.match(full, /Delete scenes you no longer need in Your scenes/);
  assert.match(full, /--scene-store-bytes or --scene-store-entries/);
  const busy = plainWords({ status: 503, problem: { retryAfter: 2 } });
  assert.match(busy, /try again in 2 s/);
  assert.match(busy, /--render-queue/);
  assert.match(plainWords({ status: 401, problem: {} }), /access token/);
  assert.equal(plainWords({ status: 422, problem: {} }), null);
});
