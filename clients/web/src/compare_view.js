// Side-by-side mode on the page: reads the pixels of the two decoded images through a canvas, draws
// their difference image (compare.js) and writes the measured error. Both renders share the view and
// the size, so their pixels correspond one to one.
import { diffImages, formatPsnr, formatShare } from "./compare.js";

function pixels(img) {
  const canvas = document.createElement("canvas");
  canvas.width = img.naturalWidth;
  canvas.height = img.naturalHeight;
  const ctx = canvas.getContext("2d", { willReadFrequently: true });
  ctx.drawImage(img, 0, 0);
  return ctx.getImageData(0, 0, canvas.width, canvas.height).data;
}

export async function showComparison(imgA, imgB, canvas, metrics, [labelA, labelB]) {
  const width = imgA.naturalWidth;
  const height = imgA.naturalHeight;
  if (width !== imgB.naturalWidth || height !== imgB.naturalHeight) {
    metrics.textContent = "The two images differ in size; nothing to compare.";
    return null;
  }
  const d = diffImages(pixels(imgA), pixels(imgB), width, height);
  canvas.width = width;
  canvas.height = height;
  canvas.getContext("2d").putImageData(new ImageData(d.image, width, height), 0, 0);
  metrics.replaceChildren();
  const rows = [
    ["differing pixels", `${formatShare(d.share)} (${d.differing.toLocaleString("en")} of ${(width * height).toLocaleString("en")})`],
    ["PSNR", formatPsnr(d.psnr)],
    ["largest channel difference", String(d.maxDiff)],
  ];
  const caption = document.createElement("p");
  caption.textContent = `${labelB} against ${labelA}: magenta marks every pixel whose colour differs.`;
  const dl = document.createElement("dl");
  for (const [k, v] of rows) {
    const dt = document.createElement("dt");
    dt.textContent = k;
    const dd = document.createElement("dd");
    dd.textContent = v;
    dd.dataset.metric = k;
    dl.append(dt, dd);
  }
  metrics.append(caption, dl);
  metrics.dataset.share = String(d.share);
  metrics.dataset.psnr = String(d.psnr);
  return d;
}

export function clearComparison(metrics) {
  metrics.replaceChildren();
  delete metrics.dataset.share;
  delete metrics.dataset.psnr;
}
