// Scenes stored on the server, in real Chromium against the real server: Save with its permalink and
// image URL, links that cannot be opened, and an interior too big for the editor imported through
// the page's file input. One CTest test per scenario.
//   node tests/browser/sharing.mjs BUILD/roomrender OUT_DIR SCENARIO
// The big import reads fireplace_room.obj, the home import Studio.xml and its furniture/, from
// ROOMRENDER_SHARED (default: ../shared next to the repository, as bench/ finds it); each is skipped
// when that is absent.
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { execFileSync } from "node:child_process";
import { runScenario, assert, skip, repoRoot, httpRequest, serverHas, imageSummary } from "./support.mjs";
import { hooks, idle, request, near, clickPlan, dragPlan, openEmpty, drawRoom, chooseItem } from "./designer_support.mjs";
import { hitTest, solidAnchor } from "../../clients/web/src/plan_math.js";

const [binary, outDir, scenario] = process.argv.slice(2);

const sharedDir = process.env.ROOMRENDER_SHARED || path.resolve(repoRoot, "../shared");
const fireplaceObj = path.join(sharedDir, "data/meshes/fireplace_room/fireplace_room.obj");
const homesDir = path.join(sharedDir, "data/floorplans/sweethome3d");

// A zip of Studio.xml and the whole furniture/ folder beside it, as a person would zip a home.
function studioZip() {
  const zip = path.join(fs.mkdtempSync(path.join(os.tmpdir(), "rr-studio-")), "Studio.zip");
  execFileSync("python3", ["-c", `import sys, os, zipfile
zip, home = sys.argv[1], sys.argv[2]
with zipfile.ZipFile(zip, "w", zipfile.ZIP_DEFLATED) as z:
    z.write(os.path.join(home, "Studio.xml"), "Studio.xml")
    for name in sorted(os.listdir(os.path.join(home, "furniture"))):
        z.write(os.path.join(home, "furniture", name), "furniture/" + name)`, zip, homesDir]);
  return zip;
}

// JSON with object keys sorted: a stored scene comes back canonical (keys sorted), so two requests
// are the same when their sorted forms are.
const sorted = (v) => (Array.isArray(v) ? v.map(sorted)
  : v && typeof v === "object" ? Object.fromEntries(Object.keys(v).sort().map((k) => [k, sorted(v[k])])) : v);
const same = (a, b) => JSON.stringify(sorted(a)) === JSON.stringify(sorted(b));

const renderSeq = (page) => page.evaluate(() => Number(document.getElementById("views").dataset.renderSeq || 0));

async function waitForNewRender(page, seq) {
  await page.waitForFunction((s) => Number(document.getElementById("views").dataset.renderSeq || 0) > s, seq);
  await idle(page);
}

// The example selector follows the editor's text a moment after it changes (the controls read the
// text debounced), so it is waited for rather than read at once.
async function expectExample(page, value, message) {
  await page.waitForFunction((v) => document.getElementById("example").value === v, value, { timeout: 5000 })
    .catch(() => assert(false, message));
}

const scenarios = {
  // Save stores the scene; the permalink opened in a new page gives the same request and the same
  // PNG bytes, and the image URL answers those bytes too. The example selector says "(custom)".
  async designer_permalink({ page, server, context }) {
    await openEmpty(page, server);
    await expectExample(page, "", "after New the example selector says (custom)");
    await drawRoom(page);
    await chooseItem(page, "Living room", "chair");
    await clickPlan(page, 2, 2);
    // A camera of one's own: two orbit steps with the keyboard on the image.
    await page.focus("#views");
    await page.keyboard.press("ArrowLeft");
    await page.keyboard.press("ArrowUp");
    await idle(page);
    assert(await page.$eval("#example option:checked", (o) => o.textContent) === "(custom)", "the selector shows (custom)");

    await page.click('[data-action="save"]');
    await page.waitForSelector("#share-links:not([hidden])");
    const link = await page.getAttribute("#permalink", "href");
    const imageUrl = await page.inputValue("#image-url");
    assert(/\/\?scene=[0-9a-f]{16}&view=/.test(link), `a permalink: ${link}`);
    assert(/\/v1\/scenes\/[0-9a-f]{16}\/render\.png\?position=/.test(imageUrl), `an image URL: ${imageUrl}`);
    const before = await request(page);
    const pngBefore = await hooks(page, "png");

    const other = await context.newPage();
    await other.goto(link);
    await other.waitForFunction(() => window.roomrenderDesigner && Number(document.getElementById("views").dataset.renderSeq || 0) > 0);
    await idle(other);
    const after = await request(other);
    assert(same(before, after), `the link gives the same request:\n${JSON.stringify(sorted(before))}\n${JSON.stringify(sorted(after))}`);
    const pngAfter = await hooks(other, "png");
    assert(pngAfter === pngBefore, `and the same PNG bytes (${pngBefore.length} / ${pngAfter.length} base64 characters)`);
    await expectExample(other, "", "a linked scene is (custom) too");

    const res = await httpRequest(imageUrl);
    assert(res.status === 200 && res.headers["content-type"] === "image/png", `the image URL answers a PNG: ${res.status}`);
    assert(res.body.toString("base64") === pngBefore, "with the bytes shown in the page");
    await other.close();
  },

  // A link to a scene the server does not have, and a scene the server refuses to store, are said
  // in the page; the page stays usable.
  async designer_share_errors({ page, server }) {
    await page.goto(`${server.url}/?scene=0123456789abcdef&view=%7B%7D`);
    await page.waitForSelector("#share-message:not([hidden])");
    const message = await page.textContent("#share-message");
    assert(/0123456789abcdef/.test(message) && /no such scene/.test(message), `the page says the scene is unknown: ${message}`);
    await page.waitForFunction(() => Number(document.getElementById("views").dataset.renderSeq || 0) > 0);
    await idle(page);
    await expectExample(page, "apartment", "and loads the default example instead");

    // A wall without an end parses as JSON but is no scene: storing it is refused, with the reason.
    const broken = await request(page);
    broken.scene.walls = [{ start: [0, 0], thickness: 0.2, height: 2.5 }];
    await page.click(".cm-content");
    await page.keyboard.press("Control+A");
    await page.keyboard.insertText(JSON.stringify(broken, null, 2));
    await page.click('[data-action="save"]');
    await page.waitForFunction(() => /HTTP 422/.test(document.getElementById("share-message").textContent));
    const refusal = await page.textContent("#share-message");
    assert(/\/walls\/0/.test(refusal) && /end/.test(refusal), `the refusal names the field: ${refusal}`);
  },

  // An OBJ interior (5.65 MB) goes through POST /v1/import/obj?store=1: the editor gets the scene
  // with its meshes kept out and a summary, renders go by id, and a light added in the plan renders.
  async designer_import_big({ page, server }) {
    const renders = [];
    page.on("request", (req) => {
      if (req.method() === "POST" && /\/v1\/(render|scenes(\/[0-9a-f]+\/render)?)$/.test(new URL(req.url()).pathname)) {
        renders.push({ path: new URL(req.url()).pathname, bytes: (req.postDataBuffer() || Buffer.alloc(0)).length });
      }
    });
    await page.goto(`${server.url}/`);
    await page.waitForFunction(() => window.roomrenderDesigner && Number(document.getElementById("views").dataset.renderSeq || 0) > 0);
    await idle(page);
    const example = await imageSummary(page);
    let seq = await renderSeq(page);
    renders.length = 0;

    await page.setInputFiles("#file", fireplaceObj);
    await waitForNewRender(page, seq);
    const status = await page.textContent("#status");
    assert(!/refused|failed/i.test(status), `the import rendered: ${status}`);
    const imported = await imageSummary(page);
    assert(imported.colours > 5 && imported.hash !== example.hash, `an image of the room: ${JSON.stringify(imported)}`);
    // The scene follows (the server compresses its megabytes first: slow on a loaded machine).
    await page.waitForFunction(() => /MB scene/.test(document.getElementById("big-summary").textContent), null, { timeout: 150000 });
    const summary = await page.textContent("#big-summary");
    assert(await page.isVisible("#big-summary") && /MB scene: .*65 solids \(6\d meshes kept out/.test(summary), `a summary: ${summary}`);
    const r = await request(page);
    const text = JSON.stringify(r);
    const kept = r.scene.solids.filter((s) => typeof s.stored_mesh === "string").length;
    assert(text.length < 1e6 && kept >= 60, `the editor holds a small text: ${text.length} characters, ${kept} meshes kept out`);
    assert(renders.length >= 1 && renders.every((x) => x.path !== "/v1/render" && x.bytes < 10000),
      `renders go by scene id, with small bodies: ${JSON.stringify(renders)}`);
    await expectExample(page, "", "the selector says (custom)");

    // A point light in the middle of the room: the scene is stored again (meshes put back) and renders.
    seq = await renderSeq(page);
    renders.length = 0;
    const b = r.scene.solids.map((s) => s.vertices).flat();
    const mid = [0, 2].map((k) => (Math.min(...b.map((v) => v[k])) + Math.max(...b.map((v) => v[k]))) / 2);
    await page.click('button[data-tool="light"]');
    await clickPlan(page, mid[0], mid[1]);
    await waitForNewRender(page, seq);
    const lit = await request(page);
    assert(lit.scene.lights.length === r.scene.lights.length + 1, "the light was added");
    const stored = renders.find((x) => x.path === "/v1/scenes");
    assert(stored && stored.bytes > 5e6, `the whole scene was stored again: ${JSON.stringify(renders)}`);
    const relit = await imageSummary(page);
    assert(relit.hash !== imported.hash, "and the image changed");
    assert(!(await page.isVisible("#problems li.error")), "without errors");
  },

  // A Sweet Home 3D home zipped with its furniture models, picked in the file input: imported with
  // store=1, its furniture drawn with the models (one piece per piece of furniture, its parts placing
  // stored meshes by ref, so the editor's text stays small), rendered; a piece dragged in the plan
  // renders again.
  async designer_import_home_zip({ page, server }) {
    const zip = studioZip();
    await page.goto(`${server.url}/`);
    await page.waitForFunction(() => window.roomrenderDesigner && Number(document.getElementById("views").dataset.renderSeq || 0) > 0);
    await idle(page);
    const example = await imageSummary(page);
    let seq = await renderSeq(page);

    await page.setInputFiles("#file", zip);
    await waitForNewRender(page, seq);
    const status = await page.textContent("#status");
    assert(!/refused|failed|error/i.test(status), `the import rendered: ${status}`);
    assert(!(await page.isVisible("#problems li.error")), "without errors");
    const imported = await imageSummary(page);
    assert(imported.colours > 20 && imported.hash !== example.hash, `an image of the home: ${JSON.stringify(imported)}`);
    const r = await request(page);
    const text = JSON.stringify(r);
    const placed = r.scene.solids.filter((s) => s.type === "piece" &&
      s.parts.every((part) => /^[0-9a-f]{16}$/.test(part.ref || "") && !part.vertices));
    assert(placed.length === 43 && text.length < 250000,
      `the editor holds Studio's 43 pieces placing ref'd meshes in a small text: ${placed.length} of ${r.scene.solids.length} solids, ${text.length} characters`);
    assert((r.scene.rooms || []).length > 0 && (r.scene.walls || []).length > 0, "with the home's rooms and walls");
    const bounds = await hooks(page, "worldToPlan", 0, 0);
    assert(Number.isFinite(bounds.x) && Number.isFinite(bounds.y), `the plan has finite bounds: ${JSON.stringify(bounds)}`);

    // Drag the topmost piece under its own anchor (its footprint is its box) 0.3 m along x: it
    // moves, and the scene renders again.
    const i = r.scene.solids.findLastIndex((s, k) => placed.includes(s) && hitTest(r.scene, solidAnchor(s), 0.05) === `/scene/solids/${k}`);
    assert(i >= 0, "a piece can be picked in the plan");
    const from = solidAnchor(r.scene.solids[i]);
    seq = await renderSeq(page);
    await page.click('button[data-tool="select"]');
    await dragPlan(page, from, [from[0] + 0.3, from[1]]);
    await waitForNewRender(page, seq);
    const moved = (await request(page)).scene.solids[i];
    assert(JSON.stringify(moved.parts) === JSON.stringify(r.scene.solids[i].parts) && near(moved.center, [from[0] + 0.3, from[1]], 0.051),
      `solid ${i} moved 0.3 m: ${JSON.stringify(r.scene.solids[i].center)} -> ${JSON.stringify(moved.center)}`);
    const after = await imageSummary(page);
    assert(after.colours > 20, `the second render is a picture: ${JSON.stringify(after)}`);
    assert(!(await page.isVisible("#problems li.error")) && !/refused|failed|error/i.test(await page.textContent("#status")),
      `the second render has no error: ${await page.textContent("#status")}`);
  },
};

const prechecks = {
  async designer_import_big(server) {
    if (!fs.existsSync(fireplaceObj)) skip(`no ${fireplaceObj} (set ROOMRENDER_SHARED to the shared data's parent)`);
    if (!(await serverHas(server, "/v1/import/{format}"))) skip("needs POST /v1/import/{format}");
  },
  async designer_import_home_zip(server) {
    if (!fs.existsSync(path.join(homesDir, "Studio.xml"))) skip(`no ${homesDir}/Studio.xml (set ROOMRENDER_SHARED to the shared data's parent)`);
    if (!(await serverHas(server, "/v1/import/{format}"))) skip("needs POST /v1/import/{format}");
  },
};

const body = scenarios[scenario];
if (!binary || !outDir || !body) {
  console.error(`usage: sharing.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")})`);
  process.exit(2);
}
process.exit(await runScenario(scenario, { binary, outDir, precheck: prechecks[scenario] }, body));
