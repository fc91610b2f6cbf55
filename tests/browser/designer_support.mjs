// Steps shared by the designer's browser tests (designer.mjs, designer_view.mjs, sharing.mjs,
// pieces.mjs, visitor.mjs, levels.mjs, exposure.mjs) and bench/designer_latency.mjs: a home of
// ../shared zipped with its furniture/ (skipped when ../shared lacks it), the page's hooks
// (window.roomrenderDesigner), choosing furniture, clicks and drags in the plan by world
// coordinates, and the empty 5 m × 4 m room drawn with the wall tool.
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { execFileSync } from "node:child_process";
import { assert, repoRoot, skip, serverHas } from "./support.mjs";

// Sweet Home 3D homes of ../shared (ROOMRENDER_SHARED names another parent directory).
export const homesDir = path.join(process.env.ROOMRENDER_SHARED || path.resolve(repoRoot, "../shared"), "data/floorplans/sweethome3d");

// Skips the scenario when home `name` is not in ../shared or the server cannot import homes.
export async function requireHome(server, name) {
  if (!fs.existsSync(path.join(homesDir, `${name}.xml`))) skip(`no ${homesDir}/${name}.xml (set ROOMRENDER_SHARED)`);
  if (!(await serverHas(server, "/v1/import/{format}"))) skip("needs POST /v1/import/{format}");
}

// A zip of the home's XML and the furniture/ folder beside it, as a person would zip a home.
export function homeZip(name) {
  const zip = path.join(fs.mkdtempSync(path.join(os.tmpdir(), "rr-home-")), `${name}.zip`);
  execFileSync("python3", ["-c", `import sys, os, zipfile
zip, home, name = sys.argv[1], sys.argv[2], sys.argv[3]
with zipfile.ZipFile(zip, "w", zipfile.ZIP_DEFLATED) as z:
    z.write(os.path.join(home, name + ".xml"), name + ".xml")
    for f in sorted(os.listdir(os.path.join(home, "furniture"))):
        z.write(os.path.join(home, "furniture", f), "furniture/" + f)`, zip, homesDir, name]);
  return zip;
}

export const hooks = (page, name, ...args) => page.evaluate(([n, a]) => window.roomrenderDesigner[n](...a), [name, args]);
export const idle = (page) => page.evaluate(() => window.roomrenderDesigner.idle());
export const request = (page) => hooks(page, "request");
export const near = (a, b, tol = 1e-6) => a.length === b.length && a.every((v, i) => Math.abs(v - b[i]) <= tol);

// Chooses a piece of furniture as a person would: the Furniture tool, then the catalogue's
// category in its selector and the model's button (a block or cylinder: its button).
export async function chooseItem(page, category, item) {
  await page.click('button[data-tool="furniture"]');
  if (category) await page.selectOption("#catalogue-category", category);
  await page.click(`[data-item="${item}"]`);
}

export async function clickPlan(page, x, z) {
  const p = await hooks(page, "worldToPlan", x, z);
  await page.mouse.click(p.x, p.y);
}

// Drags in the plan from one world point to another in `steps` pointer moves.
export async function dragPlan(page, from, to, steps = 8) {
  const a = await hooks(page, "worldToPlan", ...from);
  const b = await hooks(page, "worldToPlan", ...to);
  await page.mouse.move(a.x, a.y);
  await page.mouse.down();
  for (let i = 1; i <= steps; i++) await page.mouse.move(a.x + ((b.x - a.x) * i) / steps, a.y + ((b.y - a.y) * i) / steps);
  await page.mouse.up();
}

// Waits until the designer's hooks are there and its first render is shown, then for it to settle.
export async function designerReady(page) {
  await page.waitForFunction(() => window.roomrenderDesigner && Number(document.getElementById("views").dataset.renderSeq || 0) > 0);
  await idle(page);
}

// Waits until a render newer than `seq` is shown, then for the designer to settle.
export async function waitForNewRender(page, seq, options = {}) {
  await page.waitForFunction((s) => Number(document.getElementById("views").dataset.renderSeq || 0) > s, seq, options);
  await idle(page);
}

// Opens the page, waits for its first render, and starts an empty scene with "New".
export async function openEmpty(page, server) {
  await page.goto(`${server.url}/`);
  await designerReady(page);
  await page.click('[data-action="new"]');
  await page.waitForFunction(() => (window.roomrenderDesigner.request()?.scene?.walls || [null]).length === 0);
  await idle(page);
  const r = await request(page);
  assert(r.camera && r.scene.lights.length >= 1, `"New" gives a camera and a light: ${JSON.stringify(r)}`);
  assert(r.scene.solids.length === 0, "and nothing else");
}

export const room = [[0, 0], [5, 0], [5, 4], [0, 4]];

export async function drawRoom(page) {
  await page.click('button[data-tool="wall"]');
  await clickPlan(page, ...room[0]);
  for (let i = 1; i <= 4; i++) {
    await clickPlan(page, ...room[i % 4]);
    const walls = (await request(page)).scene.walls;
    assert(walls.length === i, `wall ${i} is added by click ${i + 1}: ${JSON.stringify(walls)}`);
    const w = walls[i - 1];
    assert(near(w.start, room[i - 1]) && near(w.end, room[i % 4]), `wall ${i} runs ${room[i - 1]} -> ${room[i % 4]}: ${JSON.stringify(w)}`);
  }
  // The click on the start point closed the chain: a further click starts a new one, adding nothing.
  await clickPlan(page, 2, 2);
  assert((await request(page)).scene.walls.length === 4, "the chain ended on its start point");
  await page.keyboard.press("Escape");
}

// Image pixel (u, v) over world point p for a request's camera and options (the inverse of
// camera.js's pixelRay).
export function worldToImage(camera, options, p) {
  const sub = (a, b) => a.map((v, i) => v - b[i]);
  const dot = (a, b) => a.reduce((s, v, i) => s + v * b[i], 0);
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const unit = (a) => a.map((v) => v / Math.hypot(...a));
  const forward = unit(sub(camera.target, camera.position));
  const right = unit(cross(forward, camera.up || [0, 1, 0]));
  const up = cross(right, forward);
  const d = sub(p, camera.position);
  const tanY = Math.tan(((camera.fov_y ?? 60) * Math.PI) / 360);
  const aspect = options.width / options.height;
  return [((dot(d, right) / dot(d, forward) / (tanY * aspect) + 1) / 2) * options.width,
    ((1 - dot(d, up) / dot(d, forward) / tanY) / 2) * options.height];
}

// The page point over world point p in the page's image.
export async function worldToPage(page, camera, options, p) {
  const [u, v] = worldToImage(camera, options, p);
  return hooks(page, "viewToPage", u - 0.5, v - 0.5);
}
