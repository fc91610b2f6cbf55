// The difference measures against hand-computed values on tiny images.
import { test } from "node:test";
import assert from "node:assert/strict";
import { diffImages, formatPsnr, formatShare } from "../src/compare.js";

const rgba = (...pixels) => new Uint8ClampedArray(pixels.flatMap((p) => [...p, 255]));

test("identical images: nothing differs, PSNR is infinite", () => {
  const a = rgba([10, 20, 30], [200, 100, 0]);
  const d = diffImages(a, a.slice(), 2, 1);
  assert.equal(d.differing, 0);
  assert.equal(d.share, 0);
  assert.equal(d.psnr, Infinity);
  assert.equal(formatPsnr(d.psnr), "∞ (identical)");
  assert.equal(d.image[0], d.image[1]);  // grey
  assert.equal(d.image[3], 255);
});

test("one of four pixels off by 255 in one channel", () => {
  const a = rgba([0, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]);
  const b = rgba([255, 0, 0], [0, 0, 0], [0, 0, 0], [0, 0, 0]);
  const d = diffImages(a, b, 2, 2);
  assert.equal(d.differing, 1);
  assert.equal(d.share, 0.25);
  assert.equal(d.maxDiff, 255);
  // MSE = 255^2 / (4 pixels * 3 channels): PSNR = 10 log10(12) dB.
  assert.ok(Math.abs(d.psnr - 10 * Math.log10(12)) < 1e-12);
  assert.deepEqual([...d.image.slice(0, 4)], [255, 0, 255, 255]);
  assert.equal(formatShare(d.share), "25.00 %");
});

test("a difference of one level is still shown", () => {
  const d = diffImages(rgba([100, 100, 100]), rgba([100, 101, 100]), 1, 1);
  assert.equal(d.differing, 1);
  assert.ok(d.image[0] >= 128 && d.image[1] === 0);
});

test("mismatched sizes are refused", () => {
  assert.throws(() => diffImages(rgba([0, 0, 0]), rgba([0, 0, 0], [0, 0, 0]), 1, 1));
});
