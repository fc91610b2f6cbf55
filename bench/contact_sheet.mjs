// A contact sheet of the Sweet Home 3D homes seen from their observer cameras with Phong and shadows:
// one row per home, columns shadow maps and exact shadow rays, each drawn by the two builds given
// (e.g. before and after a change). Each home is imported with its furniture models by each build.
//   node bench/contact_sheet.mjs OUT.png BEFORE/roomrender AFTER/roomrender [TILE_WIDTHxHEIGHT]
// Columns: map (before), map (after), rays (before), rays (after). Homes: ../shared's
// data/floorplans/sweethome3d/*.xml in name order (ROOMRENDER_SHARED names another parent directory).
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import zlib from "node:zlib";
import { execFileSync } from "node:child_process";

const [out, before, after, tile = "256x144"] = process.argv.slice(2);
if (!out || !before || !after) {
  console.error("usage: node bench/contact_sheet.mjs OUT.png BEFORE/roomrender AFTER/roomrender [WxH]");
  process.exit(2);
}
const [tw, th] = tile.split("x").map(Number);
const repo = path.resolve(path.dirname(new URL(import.meta.url).pathname), "..");
const homesDir = path.join(process.env.ROOMRENDER_SHARED || path.resolve(repo, "../shared"), "data/floorplans/sweethome3d");
const homes = fs.readdirSync(homesDir).filter((f) => f.endsWith(".xml")).sort();
const work = fs.mkdtempSync(path.join(os.tmpdir(), "rr-sheet-"));

// The pixels of an 8-bit, non-interlaced RGB or RGBA PNG as RGB rows.
function decodePng(buf) {
  let pos = 8;
  let width = 0, height = 0, channels = 0;
  const idat = [];
  while (pos < buf.length) {
    const len = buf.readUInt32BE(pos);
    const type = buf.toString("latin1", pos + 4, pos + 8);
    const data = buf.subarray(pos + 8, pos + 8 + len);
    if (type === "IHDR") {
      width = data.readUInt32BE(0);
      height = data.readUInt32BE(4);
      if (data[8] !== 8 || data[12] !== 0 || (data[9] !== 2 && data[9] !== 6)) throw new Error("8-bit RGB(A) PNGs only");
      channels = data[9] === 6 ? 4 : 3;
    } else if (type === "IDAT") idat.push(data);
    pos += 12 + len;
  }
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = width * channels;
  const cur = Buffer.alloc(stride);
  let prev = Buffer.alloc(stride);
  const rgb = Buffer.alloc(width * height * 3);
  for (let y = 0; y < height; y++) {
    const filter = raw[y * (stride + 1)];
    const line = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    for (let i = 0; i < stride; i++) {
      const a = i >= channels ? cur[i - channels] : 0;
      const b = prev[i];
      const c = i >= channels ? prev[i - channels] : 0;
      let v = line[i];
      if (filter === 1) v += a;
      else if (filter === 2) v += b;
      else if (filter === 3) v += (a + b) >> 1;
      else if (filter === 4) {
        const p = a + b - c;
        const pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c);
        v += pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      cur[i] = v & 255;
    }
    for (let x = 0; x < width; x++) for (let k = 0; k < 3; k++) rgb[(y * width + x) * 3 + k] = cur[x * channels + k];
    prev = Buffer.from(cur);
  }
  return { width, height, rgb };
}

function crc32(buf) {
  let c = ~0;
  for (const byte of buf) {
    c ^= byte;
    for (let k = 0; k < 8; k++) c = c & 1 ? (c >>> 1) ^ 0xedb88320 : c >>> 1;
  }
  return ~c >>> 0;
}

function chunk(type, data) {
  const head = Buffer.alloc(8);
  head.writeUInt32BE(data.length, 0);
  head.write(type, 4, "latin1");
  const crc = Buffer.alloc(4);
  crc.writeUInt32BE(crc32(Buffer.concat([head.subarray(4), data])), 0);
  return Buffer.concat([head, data, crc]);
}

// An RGB PNG, each row filtered by "up" (rendered interiors compress well that way).
function encodePng(width, height, rgb) {
  const stride = width * 3;
  const raw = Buffer.alloc((stride + 1) * height);
  for (let y = 0; y < height; y++) {
    raw[y * (stride + 1)] = 2;
    for (let i = 0; i < stride; i++) raw[y * (stride + 1) + 1 + i] = (rgb[y * stride + i] - (y ? rgb[(y - 1) * stride + i] : 0)) & 255;
  }
  const ihdr = Buffer.alloc(13);
  ihdr.writeUInt32BE(width, 0);
  ihdr.writeUInt32BE(height, 4);
  ihdr[8] = 8;
  ihdr[9] = 2;
  return Buffer.concat([Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]), chunk("IHDR", ihdr),
    chunk("IDAT", zlib.deflateSync(raw, { level: 9 })), chunk("IEND", Buffer.alloc(0))]);
}

const gap = 4;
const cols = 4;
const W = cols * tw + (cols + 1) * gap;
const H = homes.length * th + (homes.length + 1) * gap;
const sheet = Buffer.alloc(W * H * 3, 255);
homes.forEach((file, row) => {
  const name = file.replace(/\.xml$/, "");
  const builds = [before, after].map((binary, b) => {
    const request = path.join(work, `${name}.${b}.json`);
    fs.writeFileSync(request, execFileSync(binary, ["import", path.join(homesDir, file), "--furniture", "models"], { maxBuffer: 1 << 30 }));
    return { binary, request };
  });
  const cells = [["map", 0], ["map", 1], ["rays", 0], ["rays", 1]];
  cells.forEach(([method, b], col) => {
    const png = path.join(work, `${name}.${method}.${b}.png`);
    execFileSync(builds[b].binary, ["render", builds[b].request, "-o", png, "--size", `${tw}x${th}`, "--shading", "phong",
      "--shadows", "true", "--shadow-method", method], { stdio: ["ignore", "ignore", "ignore"] });
    const img = decodePng(fs.readFileSync(png));
    const x0 = gap + col * (tw + gap);
    const y0 = gap + row * (th + gap);
    for (let y = 0; y < Math.min(th, img.height); y++) {
      img.rgb.copy(sheet, ((y0 + y) * W + x0) * 3, y * img.width * 3, (y * img.width + Math.min(tw, img.width)) * 3);
    }
  });
  console.log(`${name}: done`);
});
fs.writeFileSync(out, encodePng(W, H, sheet));
console.log(`wrote ${out} (${W}x${H}, ${fs.statSync(out).size} bytes); rows: ${homes.map((h) => h.replace(/\.xml$/, "")).join(", ")}`);
