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
import { runScenario, assert, skip, repoRoot, httpRequest, serverHas, imageSummary, tokenFile, afterListLoad, openYourScenes, listedScenes, renderSeq, waitForRender } from "./support.mjs";
import { hooks, idle, request, near, clickPlan, dragPlan, openEmpty, drawRoom, chooseItem, designerReady, waitForNewRender } from "./designer_support.mjs";
import { hitTest, solidAnchor } from "../../clients/web/src/plan_math.js";

const [binary, outDir, scenario] = process.argv.slice(2);

const sharedDir = process.env.ROOMRENDER_SHARED || path.resolve(repoRoot, "../shared");
const fireplaceObj = path.join(sharedDir, "data/meshes/fireplace_room/fireplace_room.obj");
const conferenceObj = path.join(sharedDir, "data/meshes/conference/conference.obj");
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

const aliceToken = "alice-browser-test-token-0123456789";

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
    await designerReady(other);
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
    await designerReady(page);
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

  // A store of one scene (--scene-store-entries 1) holds the first Save; a second scene's Save gets
  // 507, said in plain words with what to do, in the share panel and on no line of the editor; the
  // camera still moves and renders (inline, as the page cannot store a working copy). Deleting the
  // first scene in Your scenes (an open server with --allow-listing 1) makes room: Save then stores.
  async designer_store_full({ page, server }) {
    await page.goto(`${server.url}/?example=studio`);
    await designerReady(page);
    await page.click('[data-action="save"]');
    await page.waitForFunction(() => /Stored as scene/.test(document.getElementById("status").textContent));
    await page.click('[data-action="new"]');
    await idle(page);
    await page.click('[data-action="save"]');
    await page.waitForFunction(() => /HTTP 507/.test(document.getElementById("share-message").textContent));
    const message = await page.textContent("#share-message");
    assert(/store is full/.test(message) && /Delete scenes you no longer need in Your scenes/.test(message) &&
      /--scene-store-entries/.test(message), `the 507 is said in plain words, with what to do: ${message}`);
    assert(await page.isVisible("#share-message"), "where the user sees it");
    assert(!(await page.$(".cm-lintRange-error, .cm-inline-error")), "and marks no line of the editor");
    const seq = await renderSeq(page);
    await page.focus("#views");
    await page.keyboard.press("ArrowLeft");
    await waitForRender(page, seq);
    await idle(page);
    assert(/Rendered in/.test(await page.textContent("#status")), `the camera still renders: ${await page.textContent("#status")}`);

    await openYourScenes(page);
    const listed = await listedScenes(page);
    assert(listed.length === 1, `Your scenes lists the one stored scene: ${JSON.stringify(listed)}`);
    await page.getByRole("button", { name: `Delete scene ${listed[0]}` }).click();
    await afterListLoad(page, () => page.getByRole("button", { name: `Confirm: delete scene ${listed[0]}` }).click());
    assert((await listedScenes(page)).length === 0, "the list updates: it is empty");
    assert((await httpRequest(`${server.url}/v1/scenes/${listed[0]}`)).status === 404, "the scene is gone from the server");
    await afterListLoad(page, () => page.click('[data-action="save"]'));
    const stored = /Stored as scene ([0-9a-f]{16})/.exec(await page.textContent("#status"));
    assert(stored, `with room in the store, Save stores: ${await page.textContent("#status")}`);
    assert(JSON.stringify(await listedScenes(page)) === JSON.stringify([stored[1]]), "and the list shows the scene saved");
  },

  // Your scenes on a server with tokens (--api-token-file): without a token the list asks for one;
  // with it (typed, Enter), the two scenes Saved are listed newest first; the older one is opened
  // with the keyboard and becomes the working scene; deleting the other asks first (Escape keeps
  // it), then deletes it on the server and the list updates.
  async designer_your_scenes({ page, server }) {
    await page.goto(`${server.url}/?example=studio`);
    await designerReady(page);
    await openYourScenes(page);
    const asks = await page.textContent("#scenes-message");
    assert(/access token/.test(asks) && await page.getByLabel("Access token").isVisible(), `the list asks for a token: ${asks}`);
    await page.getByLabel("Access token").fill(aliceToken);
    await afterListLoad(page, () => page.keyboard.press("Enter"));
    assert((await listedScenes(page)).length === 0 && /No stored scenes/.test(await page.textContent("#scenes-message")),
      `none yet: ${await page.textContent("#scenes-message")}`);

    const saveAndList = async () => {
      await afterListLoad(page, () => page.click('[data-action="save"]'));
      return (/Stored as scene ([0-9a-f]{16})/.exec(await page.textContent("#status")) || [])[1];
    };
    const studio = await saveAndList();
    const studioScene = await request(page);
    await page.getByLabel("Example").selectOption("apartment");
    await page.waitForFunction(() => document.getElementById("status").textContent.startsWith("Rendered"));
    await idle(page);
    const apartment = await saveAndList();
    assert(studio && apartment && studio !== apartment, `two scenes stored: ${studio}, ${apartment}`);
    const listed = await listedScenes(page);
    assert(JSON.stringify(listed) === JSON.stringify([apartment, studio]), `listed newest first: ${JSON.stringify(listed)}`);
    const row = page.locator(`#scenes-list li[data-id="${studio}"]`);
    assert(/\d+(\.\d)? (B|KB)/.test(await row.textContent()) && (await row.locator("time").getAttribute("datetime")),
      `a row shows the size and date: ${await row.textContent()}`);

    // Tab from Refresh to the studio's Open button, then Enter.
    await page.getByRole("button", { name: "Refresh the list" }).focus();
    const openLabel = `Open scene ${studio}`;
    for (let i = 0; i < 6 && (await page.evaluate(() => document.activeElement.getAttribute("aria-label"))) !== openLabel; i++) {
      await page.keyboard.press("Tab");
    }
    assert(await page.evaluate(() => document.activeElement.getAttribute("aria-label")) === openLabel, "Tab reaches the Open button");
    const seq = await renderSeq(page);
    await page.keyboard.press("Enter");
    await waitForNewRender(page, seq);
    const opened = await request(page);
    assert(same(opened.scene, studioScene.scene), "the opened scene is the studio's");
    await page.waitForFunction(() => /working scene/.test(document.getElementById("scenes-message").textContent));
    assert(/open here/.test(await row.textContent()), "its row says it is open here");

    // Delete the apartment: the row asks first; Escape keeps it, the confirmation deletes it.
    await page.getByRole("button", { name: `Delete scene ${apartment}` }).click();
    assert(await page.evaluate(() => document.activeElement.textContent) === "Cancel", "the question focuses Cancel");
    await page.keyboard.press("Escape");
    assert(await page.getByRole("button", { name: `Delete scene ${apartment}` }).isVisible(), "Escape keeps the scene");
    await page.getByRole("button", { name: `Delete scene ${apartment}` }).click();
    await afterListLoad(page, () => page.getByRole("button", { name: `Confirm: delete scene ${apartment}` }).click());
    assert(JSON.stringify(await listedScenes(page)) === JSON.stringify([studio]), `the list updates: ${JSON.stringify(await listedScenes(page))}`);
    assert((await httpRequest(`${server.url}/v1/scenes/${apartment}`)).status === 404, "the apartment is gone from the server");
    assert((await httpRequest(`${server.url}/v1/scenes/${studio}`)).status === 200, "the studio stays");
  },

  // A bare Studio.xml (no furniture/ beside it), opened with Open file…: its pieces are boxes, and a
  // hint (from the import's warning of the models not found) says how to get the models; New takes
  // the hint away.
  async designer_import_bare_home({ page, server }) {
    await page.goto(`${server.url}/`);
    await designerReady(page);
    assert(!(await page.isVisible("#import-hint")), "no hint before an import");
    const seq = await renderSeq(page);
    const chooser = page.waitForEvent("filechooser");
    await page.getByRole("button", { name: "Open file…" }).click();
    await (await chooser).setFiles(path.join(homesDir, "Studio.xml"));
    await waitForNewRender(page, seq);
    await page.waitForSelector("#import-hint:not([hidden])");
    const hint = await page.textContent("#import-hint");
    assert(/^Studio\.xml came without its furniture models \(\d+ furniture models not found\), so those pieces are drawn as boxes/.test(hint) &&
      /open the \.sh3d file/.test(hint) && /zip Home\.xml together with its furniture\/ folder/.test(hint), `the hint says how to get the models: ${hint}`);
    const r = await request(page);
    assert(r.scene.solids.filter((s) => s.type === "box").length === 43, "Studio's 43 pieces are boxes");
    assert(await page.getByRole("status").filter({ hasText: "drawn as boxes" }).isVisible(), "as a status the user sees");
    await page.click('[data-action="new"]');
    assert(!(await page.isVisible("#import-hint")), "New takes the hint away");
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
    await designerReady(page);
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
    await designerReady(page);
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
  // The millimetre conference room imported with Units "mm": the server gets scale=0.001 and answers
  // a first view from inside (the eye within the room's box), and the image is mostly the room.
  async designer_import_obj_inside({ page, server }) {
    await page.goto(`${server.url}/`);
    await page.waitForFunction(() => window.roomrenderDesigner && Number(document.getElementById("views").dataset.renderSeq || 0) > 0);
    await idle(page);
    const seq = await renderSeq(page);
    await page.click(".import-options summary");
    // A custom factor of 0 is refused by the page, saying so, and nothing is sent.
    let imports = 0;
    page.on("request", (r) => { if (new URL(r.url()).pathname === "/v1/import/obj") imports++; });
    await page.selectOption("#import-units", "custom");
    await page.fill("#import-scale", "0");
    const [refused] = await Promise.all([page.waitForEvent("filechooser"), page.click("#open-file")]);
    await refused.setFiles(conferenceObj);
    await page.waitForFunction(() => /not a number of metres per unit above 0/.test(document.getElementById("status").textContent));
    await idle(page);
    assert(imports === 0, `a scale of 0 sends no import: ${imports} sent`);
    assert(await page.getAttribute("#import-scale", "aria-invalid") !== null, "the scale field is marked invalid");
    await page.selectOption("#import-units", "0.001");
    const answer = page.waitForResponse((res) => new URL(res.url()).pathname === "/v1/import/obj");
    const [chooser] = await Promise.all([page.waitForEvent("filechooser"), page.click("#open-file")]);
    await chooser.setFiles(conferenceObj);
    const res = await answer;
    assert(new URL(res.url()).searchParams.get("scale") === "0.001", `the import asks scale=0.001: ${res.url()}`);
    await waitForNewRender(page, seq);
    const { camera } = await request(page);
    // The room in metres (the file's box / 1000, measured once from conference.obj).
    const lo = [-1.021, -0.003, -1.056], hi = [1.686, 0.651, 0.669];
    assert(camera.position.every((v, k) => v > lo[k] && v < hi[k]) && camera.near <= 0.05,
      `the first view is from inside: ${JSON.stringify(camera)}`);
    const background = await page.evaluate(() => {
      const img = document.getElementById("image");
      const canvas = Object.assign(document.createElement("canvas"), { width: img.naturalWidth, height: img.naturalHeight });
      const ctx = canvas.getContext("2d");
      ctx.drawImage(img, 0, 0);
      const data = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
      let same = 0;  // pixels of the importer's background, #20242a
      for (let i = 0; i < data.length; i += 4) same += data[i] === 0x20 && data[i + 1] === 0x24 && data[i + 2] === 0x2a;
      return same / (data.length / 4);
    });
    assert(background < 0.1, `the image is the room, not the background: ${(background * 100).toFixed(1)}% background`);
  },
};

const prechecks = {
  async designer_import_obj_inside(server) {
    if (!fs.existsSync(conferenceObj)) skip(`no ${conferenceObj} (set ROOMRENDER_SHARED to the shared data's parent)`);
    if (!(await serverHas(server, "/v1/import/{format}"))) skip("needs POST /v1/import/{format}");
  },

  async designer_your_scenes(server) {
    if (!(await serverHas(server, "/v1/scenes", "get"))) skip("needs GET /v1/scenes");
  },
  async designer_import_bare_home(server) {
    if (!fs.existsSync(path.join(homesDir, "Studio.xml"))) skip(`no ${homesDir}/Studio.xml (set ROOMRENDER_SHARED to the shared data's parent)`);
    if (!(await serverHas(server, "/v1/import/{format}"))) skip("needs POST /v1/import/{format}");
  },
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
const serverArgs = {
  designer_store_full: () => ["--scene-store-entries", "1", "--allow-listing", "1"],
  designer_your_scenes: () => ["--api-token-file", tokenFile({ alice: aliceToken })],
};
process.exit(await runScenario(scenario, { binary, outDir, precheck: prechecks[scenario], serverArgs: serverArgs[scenario]?.() }, body));
