// Interaction latency of the web page's designer (a benchmark, not a test): the time from one drag
// step to the reduced-size (320×240) image of that step being on screen, for the apartment example
// at 640×480, in real Chromium against the real server on loopback.
//   node bench/designer_latency.mjs BUILD/roomrender [--steps 50] [--home NAME] [--web-dir DIR] [--out bench/results/designer_latency.json]
// (--web-dir serves another build of the page, e.g. the previous index.html, for a before/after.)
// Three drags: orbit on the 3D view, moving chair_north in the plan (select tool, 10 cm a step), and
// moving it on the 3D image (the press picks it through POST /v1/pick; 10 cm a step on the floor).
// A step is one pointer move; the next step starts once the image of the previous one is shown, so
// each step gets its own render (none is aborted by the next). The clock runs in the page: from the
// pointermove event to the first animation frame after the new image was decoded and put in place.
// Then a live orbit, as a hand drags: pointer moves every 16.7 ms for 2 s, not waiting for images,
// on the apartment example and on a Sweet Home 3D home of ../shared imported with its furniture/
// (--home, default 3BedroomApartment; skipped without ../shared) as it opens (Phong with exact
// shadows), then flat without shadows chosen in the toolbar: images shown a second while the
// drag goes on, main-thread task time per camera step (Chromium's TaskDuration between two moves,
// so it counts the answers' handling too; and its ThreadTime, the main thread's CPU time, which
// leaves out waiting for a core), and the time from the release to the full-size image.
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { createRequire } from "node:module";
import { startServer, chromiumPath, repoRoot } from "../tests/browser/support.mjs";
import { worldToPage, homeZip, homesDir } from "../tests/browser/designer_support.mjs";

const args = process.argv.slice(2);
const binary = args[0];
const option = (name, fallback) => (args.includes(name) ? args[args.indexOf(name) + 1] : fallback);
const steps = Number(option("--steps", 50));
const outPath = option("--out", path.join(repoRoot, "bench/results/designer_latency.json"));
const homeName = option("--home", "3BedroomApartment");
if (!binary) {
  console.error("usage: designer_latency.mjs ROOMRENDER [--steps N] [--home NAME] [--web-dir DIR] [--out FILE]");
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

const seqOf = (page) => page.evaluate(() => Number(document.getElementById("views").dataset.renderSeq || 0));
const sleep = (ms) => new Promise((done) => setTimeout(done, ms));

// A pixel of the image where a press orbits: the nearest to the centre (on a 40 px grid) where the
// server's pick finds no solid (a press on a solid would move it).
async function orbitPixel(page, server) {
  const request = await page.evaluate(() => window.roomrenderDesigner.request());
  const { width, height } = request.options;
  const candidates = [];
  for (let y = 20; y < height; y += 40) for (let x = 20; x < width; x += 40) candidates.push([x, y]);
  candidates.sort((a, b) => Math.hypot(a[0] - width / 2, a[1] - height / 2) - Math.hypot(b[0] - width / 2, b[1] - height / 2));
  for (const [x, y] of candidates) {
    const res = await fetch(`${server.url}/v1/pick`, { method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify({ ...request, x, y }) });
    const hit = await res.json();
    if (res.ok && !/^\/scene\/solids\//.test(hit.pointer || "")) return [x, y];
  }
  throw new Error("no pixel of the image is free of solids");
}

// The live orbit: `moves` pointer moves of 4 px, one every 16.7 ms from near the image's centre, the
// button held (from a pixel where a press orbits rather than grabs a solid); the images of reduced
// width shown meanwhile are counted. Chromium's TaskDuration
// (main-thread task time) is read between two moves: its difference is one camera step's work. After
// the release, the time to the full-size image on screen (the first frame after it is in place).
async function measureLiveOrbit(page, cdp, server, moves = 120) {
  // TaskDuration is wall time of the main thread's tasks: on a 2-core machine that also runs the
  // server's render threads it counts time the main thread waited for a core. ThreadTime is the
  // main thread's own CPU time; both are reported.
  const taskMs = async () => {
    const metrics = (await cdp.send("Performance.getMetrics")).metrics;
    const value = (name) => metrics.find((m) => m.name === name).value * 1000;
    return { task: value("TaskDuration"), cpu: value("ThreadTime") };
  };
  await page.evaluate(() => window.roomrenderDesigner.idle());
  const width = (await page.evaluate(() => window.roomrenderDesigner.request().options)).width;
  await page.evaluate((w) => {
    const live = { shown: 0, releasedAt: 0, fullAt: 0 };
    window.liveClock = live;
    document.addEventListener("pointerup", () => { live.releasedAt = performance.now(); }, { capture: true, once: true });
    new MutationObserver(() => {
      const n = document.getElementById("image").naturalWidth;
      if (!live.releasedAt && n < w) live.shown++;
      else if (live.releasedAt && !live.fullAt && n === w) requestAnimationFrame(() => { live.fullAt = performance.now(); });
    }).observe(document.getElementById("views"), { attributes: true, attributeFilter: ["data-render-seq"] });
  }, width);
  const [u, v] = await orbitPixel(page, server);
  const centre = await page.evaluate(([a, b]) => window.roomrenderDesigner.viewToPage(a, b), [u, v]);
  // The moves, paced at 60 a second; the main-thread task time between two moves.
  const paced = async () => {
    const perMove = [], cpuPerMove = [];
    const started = performance.now();
    let before = await taskMs();
    for (let i = 1; i <= moves; i++) {
      await page.mouse.move(centre.x + 4 * (i <= moves / 2 ? i : moves - i), centre.y);
      const due = started + i * (1000 / 60);
      if (performance.now() < due) await sleep(due - performance.now());
      const now = await taskMs();
      perMove.push(now.task - before.task);
      cpuPerMove.push(now.cpu - before.cpu);
      before = now;
    }
    return { perMove, cpuPerMove, seconds: (performance.now() - started) / 1000 };
  };
  // The same moves without the button: no camera step, what the harness and the browser cost alone.
  await page.mouse.move(centre.x, centre.y);
  const { perMove: baseline, cpuPerMove: cpuBaseline } = await paced();
  await page.mouse.move(centre.x, centre.y);
  await page.mouse.down();
  const { perMove: perStep, cpuPerMove: cpuPerStep, seconds } = await paced();
  const shown = await page.evaluate(() => window.liveClock.shown);
  await page.mouse.up();
  // A page that drew the full size during the drag (a step took longer than its rest delay) may
  // draw none after the release: then null.
  await page.waitForFunction(() => window.liveClock.fullAt > 0, null, { timeout: 20000 }).catch(() => {});
  const release = await page.evaluate(() => (window.liveClock.fullAt ? window.liveClock.fullAt - window.liveClock.releasedAt : null));
  await page.evaluate(() => window.roomrenderDesigner.idle());
  return { moves, drag_seconds: round(seconds), images_shown: shown, images_per_second: round(shown / seconds),
    main_thread_per_step: summary(perStep), full_size_after_release_ms: release === null ? null : round(release),
    main_thread_busy_share: round(perStep.reduce((a, b) => a + b, 0) / (seconds * 1000)),
    main_thread_per_move_without_button: summary(baseline),
    main_thread_cpu_per_step: summary(cpuPerStep), main_thread_cpu_per_move_without_button: summary(cpuBaseline) };
}

const require = createRequire(path.join(repoRoot, "clients/web/package.json"));
const { chromium } = require("playwright-core");
const loadBefore = os.loadavg();
const webDir = option("--web-dir", null);
const server = await startServer(binary, webDir ? ["--web-dir", path.resolve(webDir)] : []);
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

  // The live orbit on the apartment example, then on the imported home at 640×480.
  const cdp = await page.context().newCDPSession(page);
  await cdp.send("Performance.enable");
  await page.goto(`${server.url}/?example=apartment`);
  await page.waitForFunction(() => window.roomrenderDesigner && Number(document.getElementById("views").dataset.renderSeq || 0) > 0);
  const liveApartment = await measureLiveOrbit(page, cdp, server);
  let liveHome = null;
  let liveHomeShadows = null;
  if (fs.existsSync(path.join(homesDir, `${homeName}.xml`))) {
    const seq = await seqOf(page);
    await page.setInputFiles("#file", homeZip(homeName));
    await page.waitForFunction((s) => Number(document.getElementById("views").dataset.renderSeq || 0) > s, seq, { timeout: 120000 });
    await page.evaluate(() => window.roomrenderDesigner.idle());
    await page.selectOption("#size", "640x480");
    await page.evaluate(() => window.roomrenderDesigner.idle());
    const chars = await page.evaluate(() => JSON.stringify(window.roomrenderDesigner.request()).length);
    // The home with Phong and exact shadows (as it opens; a page that opens it otherwise gets them
    // chosen in the toolbar), then flat without shadows, chosen in the toolbar as a person would.
    const opened = await page.evaluate(() => window.roomrenderDesigner.request().options);
    await page.selectOption("#shading", "phong");
    await page.selectOption("#shadow-method", "rays");
    await page.check("#shadows");
    await page.evaluate(() => window.roomrenderDesigner.idle());
    const options = await page.evaluate(() => window.roomrenderDesigner.request().options);
    if (options.shading !== "phong" || options.shadows !== true || options.shadow?.method !== "rays") {
      throw new Error(`the toolbar did not set Phong with exact shadows: ${JSON.stringify(options)}`);
    }
    liveHomeShadows = { home: homeName, opened_with: opened, options: { shading: "phong", shadows: true, shadow: { method: "rays" } },
      ...(await measureLiveOrbit(page, cdp, server)) };
    await page.selectOption("#shading", "flat");
    await page.evaluate(() => window.roomrenderDesigner.idle());
    await page.uncheck("#shadows");
    await page.evaluate(() => window.roomrenderDesigner.idle());
    liveHome = { home: homeName, request_chars: chars, options: { shading: "flat", shadows: false },
      ...(await measureLiveOrbit(page, cdp, server)) };
  }

  const result = {
    what: "time from one drag step (pointermove) to the 320×240 image of that step on screen (first frame after it is decoded); apartment example, 640×480, zbuffer, flat",
    machine: { cpus: os.cpus().length, load_average_before: loadBefore.map(round), load_average_after: os.loadavg().map(round),
      note: "shared 2-core machine: the load averages say what else ran" },
    notes: "Steps are paced by their images (the next move waits for the last step's image). When a step's half-size image " +
      "takes over 0.25 s, the page asks for the full size at rest; the next move aborts that request, but the server still " +
      "draws it, and the next step waits behind it: that is the slow mode of the orbit samples (~1 s). The plan drag asks " +
      "for no rest render while the button is held.",
    chromium: browser.version(),
    web_dir: webDir,
    orbit: summary(orbit),
    plan_move_chair: { ...summary(plan), chair_back_at_start: Math.abs(moved.center[0] - chair.center[0]) < 1e-6 },
    view_move_chair: { ...summary(view), chair_back_at_start: Math.abs(movedInView.center[0] - chair.center[0]) < 0.051 },
    live_orbit: { what: "pointer moves every 16.7 ms for 2 s, not paced by images; 4 px each (1.6° of azimuth); 640×480, the page's pipeline and options",
      apartment: liveApartment, home: liveHome, home_phong_exact_shadows: liveHomeShadows },
  };
  fs.mkdirSync(path.dirname(outPath), { recursive: true });
  fs.writeFileSync(outPath, JSON.stringify(result, null, 2) + "\n");
  console.log(`orbit: median ${result.orbit.median_ms} ms, p90 ${result.orbit.p90_ms} ms; ` +
    `plan (chair): median ${result.plan_move_chair.median_ms} ms, p90 ${result.plan_move_chair.p90_ms} ms; ` +
    `3D image (chair): median ${result.view_move_chair.median_ms} ms, p90 ${result.view_move_chair.p90_ms} ms; ` +
    [["apartment", liveApartment], [homeName, liveHome], [`${homeName} phong+rays`, liveHomeShadows]].filter(([, r]) => r).map(([n, r]) =>
      `live orbit ${n}: ${r.images_per_second} images/s, main thread p90 ${r.main_thread_per_step.p90_ms} ms a step ` +
      `(its CPU time p90 ${r.main_thread_cpu_per_step.p90_ms} ms), ` +
      `full size ${r.full_size_after_release_ms} ms after release; `).join("") +
    `load ${loadBefore[0].toFixed(1)} -> ${os.loadavg()[0].toFixed(1)}; wrote ${outPath}`);
} finally {
  await browser.close();
  await server.stop();
}
