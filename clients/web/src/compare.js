// Difference of two renders of the same view (side-by-side mode). In: two RGBA pixel arrays of the
// same width and height (canvas ImageData layout, row-major from the top-left). Out: the share of
// pixels whose colour differs at all, the PSNR of B against A over the RGB channels (8-bit peak, as
// the accuracy work measures it), the largest channel difference, and a difference image: identical
// pixels as a dimmed grey copy of A, differing ones in magenta, brighter for larger differences.
export function diffImages(a, b, width, height) {
  const n = width * height;
  if (a.length !== n * 4 || b.length !== n * 4) {
    throw new Error(`images must both be ${width}x${height} RGBA`);
  }
  const image = new Uint8ClampedArray(n * 4);
  let differing = 0;
  let squaredError = 0;
  let maxDiff = 0;
  for (let p = 0; p < n * 4; p += 4) {
    const dr = a[p] - b[p];
    const dg = a[p + 1] - b[p + 1];
    const db = a[p + 2] - b[p + 2];
    const d = Math.max(Math.abs(dr), Math.abs(dg), Math.abs(db));
    squaredError += dr * dr + dg * dg + db * db;
    if (d > maxDiff) maxDiff = d;
    if (d > 0) {
      differing += 1;
      // Even a difference of 1 must be visible: start at half intensity.
      const v = 128 + Math.round((127 * d) / 255);
      image[p] = v;
      image[p + 1] = 0;
      image[p + 2] = v;
    } else {
      const grey = Math.round((0.299 * a[p] + 0.587 * a[p + 1] + 0.114 * a[p + 2]) * 0.35);
      image[p] = image[p + 1] = image[p + 2] = grey;
    }
    image[p + 3] = 255;
  }
  const mse = n > 0 ? squaredError / (n * 3) : 0;
  return {
    differing,
    share: n > 0 ? differing / n : 0,
    mse,
    psnr: mse === 0 ? Infinity : 10 * Math.log10((255 * 255) / mse),
    maxDiff,
    image,
  };
}

export function formatPsnr(psnr) {
  return Number.isFinite(psnr) ? `${psnr.toFixed(2)} dB` : "∞ (identical)";
}

export function formatShare(share) {
  if (share === 0) return "0 %";
  if (share < 0.0001) return "< 0.01 %";
  return `${(share * 100).toFixed(2)} %`;
}
