// Interaction latency of the web page's designer (a benchmark, not a test): the time from one drag
// step to the reduced-size (320×240) image of that step being on screen, for the apartment example
// at 640×480, in real Chromium against the real server on loopback.
//   node bench/designer_latency.mjs BUILD/roomrender [--steps 50] [--out bench/results/designer_latency.json]
// Three drags: orbit on the 3D view, moving chair_north in the plan (select tool, 10 cm a step), and
// moving it on the 3D image (the press picks it through POST /v1/pick; 10 cm a step on the floor).
// A step is one pointer move; the next step starts once the image of the previous one is shown, so
// each step gets its own render (none is aborted by the next). The clock runs in the page: from the
// pointermove event to the first animation frame after the new image was decoded and put in place.
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { createRequire } from "node:module";
import { startServer, chromiumPath, repoRoot } from "../tests/browser/support.mjs";
import { worldToPage } from "../tests/browser/designer_support.mjs";

const args = process.argv.slice(2);
const binary = args[0];
const option = (name, fallback) => (args.includes(name) ? args[args.indexOf(name) + 1] : fallback);
const steps = Number(option("--steps", 50));
const outPath = option("--out", path.join(repoRoot, "bench/results/designer_latency.json"));
if (!binary) {
  console.error("usage: designer_latency.mjs ROOMRENDER [--steps N] [--out FILE]");
  process.exit(2);
}

const quantile = (xs, q) => {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.max(0, Math.ceil(q * s.length) - 1))];
};
const summary = (xs) => ({ steps: xs.length, median_ms: round(quantile(xs, 0.5)), p90_ms: round(quantile(xs, 0.9)),
  min_ms: round(Math.min(...xs)), max_ms: round(Math.max(...xs)), samples_ms: xs.map(round) });
const round = (v) => Math.round(v * 10) / 10;

// In the page: the clock starts at a step's pointermove and stops at the first frame after an image
// of the reduced width is in place (display() sets data-render-seq once it is decoded).
function installClock(page) {
  return page.evaluate(() => {
    const clock = { start: 0, samples: [] };
    window.latencyClock = clock;
    document.addEventListener("pointermove", () => { if (!clock.start) clock.start = performance.now(); }, true);
    new MutationObserver(() => {
      if (!clock.start || document.getElementById("image").naturalWidth !== 320) return;
      const start = clock.start;
      clock.start = 0;
      requestAnimationFrame(() => clock.samples.push(performance.now() - start));
    }).observe(document.getElementById("views"), { attributes: true, attributeFilter: ["data-render-seq"] });
  });
}

const sampleCount = (page) => page.evaluate(() => window.latencyClock.samples.length);

// Moves the pointer through `points` (page pixels), button held, one measured step each. After the
// press the page is let settle (a press on the image waits for its pick), so no step counts it.
async function measureDrag(page, points) {
  await page.evaluate(() => { window.latencyClock.samples = []; window.latencyClock.start = 0; });
  await page.mouse.move(points[0].x, points[0].y);
  await page.mouse.down();
  await page.evaluate(() => window.roomrenderDesigner.idle());
  await page.evaluate(() => { window.latencyClock.start = 0; });
  for (let i = 1; i < points.length; i++) {
    const before = await sampleCount(page);
    await page.mouse.move(points[i].x, points[i].y);
    await page.waitForFunction((n) => window.latencyClock.samples.length > n, before, { timeout: 60000 });
  }
  await page.mouse.up();
  await page.evaluate(() => window.roomrenderDesigner.idle());
  return page.evaluate(() => window.latencyClock.samples.slice());
}

const require = createRequire(path.join(repoRoot, "clients/web/package.json"));
const { chromium } = require("playwright-core");
const loadBefore = os.loadavg();
const server = await startServer(binary);
const browser = await chromium.launch({ executablePath: chromiumPath(), args: ["--no-sandbox"] });
try {
  const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
  await page.goto(`${server.url}/?example=apartment`);
  await page.waitForFunction(() => window.roomrenderDesigner && Number(document.getElementById("views").dataset.renderSeq || 0) > 0);
  await page.evaluate(() => window.roomrenderDesigner.idle());
  const request = await page.evaluate(() => window.roomrenderDesigner.request());
  if (request.options.width !== 640 || request.options.height !== 480) throw new Error("the apartment is not 640×480");
  await installClock(page);

  // Orbit: 4 px a step (1.6° of azimuth), from the middle of the image.
  const centre = await page.evaluate(() => window.roomrenderDesigner.viewToPage(320, 240));
  const orbitPoints = Array.from({ length: steps + 1 }, (_, i) => ({ x: centre.x + 4 * i, y: centre.y }));
  const orbit = await measureDrag(page, orbitPoints);

  // The plan: chair_north 10 cm a step, east for half the steps, then back west.
  await page.click('[data-tool="select"]');
  const chair = request.scene.solids.find((s) => s.id === "chair_north");
  const xs = Array.from({ length: steps + 1 }, (_, i) => chair.center[0] + 0.1 * (i <= steps / 2 ? i : steps - i));
  const planPoints = [];
  for (const x of xs) planPoints.push(await page.evaluate(([a, b]) => window.roomrenderDesigner.worldToPlan(a, b), [x, chair.center[1]]));
  const plan = await measureDrag(page, planPoints);
  const moved = (await page.evaluate(() => window.roomrenderDesigner.request())).scene.solids.find((s) => s.id === "chair_north");

  // The 3D image: the same chair grabbed at the middle of its top, the grabbed point moved 10 cm a step on the
  // horizontal plane through it, east then back west.
  const y = chair.size[1];  // the top face: what the camera above sees and the press picks
  const viewPoints = [];
  for (const x of xs) viewPoints.push(await worldToPage(page, request.camera, { width: 640, height: 480 }, [x, y, chair.center[1]]));
  const view = await measureDrag(page, viewPoints);
  const movedInView = (await page.evaluate(() => window.roomrenderDesigner.request())).scene.solids.find((s) => s.id === "chair_north");

  const result = {
    what: "time from one drag step (pointermove) to the 320×240 image of that step on screen (first frame after it is decoded); apartment example, 640×480, zbuffer, flat",
    machine: { cpus: os.cpus().length, load_average_before: loadBefore.map(round), load_average_after: os.loadavg().map(round),
      note: "shared 2-core machine, other engineers compiling C++ meanwhile: the numbers include their load" },
    notes: "Steps are paced by their images (the next move waits for the last step's image). When a step's half-size image " +
      "takes over 0.25 s, the page asks for the full size at rest; the next move aborts that request, but the server still " +
      "draws it, and the next step waits behind it: that is the slow mode of the orbit samples (~1 s). The plan drag asks " +
      "for no rest render while the button is held.",
    chromium: browser.version(),
    orbit: summary(orbit),
    plan_move_chair: { ...summary(plan), chair_back_at_start: Math.abs(moved.center[0] - chair.center[0]) < 1e-6 },
    view_move_chair: { ...summary(view), chair_back_at_start: Math.abs(movedInView.center[0] - chair.center[0]) < 0.051 },
  };
  fs.mkdirSync(path.dirname(outPath), { recursive: true });
  fs.writeFileSync(outPath, JSON.stringify(result, null, 2) + "\n");
  console.log(`orbit: median ${result.orbit.median_ms} ms, p90 ${result.orbit.p90_ms} ms; ` +
    `plan (chair): median ${result.plan_move_chair.median_ms} ms, p90 ${result.plan_move_chair.p90_ms} ms; ` +
    `3D image (chair): median ${result.view_move_chair.median_ms} ms, p90 ${result.view_move_chair.p90_ms} ms; ` +
    `load ${loadBefore[0].toFixed(1)} -> ${os.loadavg()[0].toFixed(1)}; wrote ${outPath}`);
} finally {
  await browser.close();
  await server.stop();
}
