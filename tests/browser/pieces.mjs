// Furniture as pieces in real Chromium against the real server, mouse and keyboard only: a Sweet
// Home 3D home's sofa (one piece of its model's parts) dragged 1 m in the plan and on the 3D image,
// each undone by one Ctrl+Z, turned and deleted, picked whole; its warnings listed per piece; and a
// chair of the catalogue dropped in a drawn room, seen in the image with its real shape, and reloaded
// from its permalink. One CTest test per scenario.
//   node tests/browser/pieces.mjs BUILD/roomrender OUT_DIR SCENARIO
// pieces_home reads 3BedroomApartment.xml and its furniture/ from ROOMRENDER_SHARED (default:
// ../shared next to the repository) and is skipped when that is absent.
import fs from "node:fs";
import path from "node:path";
import { execFileSync } from "node:child_process";
import { runScenario, assert, skip, repoRoot, httpRequest, serverHas, imageSummary, renderSeq } from "./support.mjs";
import { hooks, idle, request, near, clickPlan, dragPlan, openEmpty, drawRoom, chooseItem, worldToPage, homeZip, designerReady, waitForNewRender, requireHome } from "./designer_support.mjs";
import { hitTest, resizeHandles } from "../../clients/web/src/plan_math.js";

const [binary, outDir, scenario] = process.argv.slice(2);
async function pick(server, body) {
  const res = await httpRequest(`${server.url}/v1/pick`, {
    method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body),
  });
  assert(res.status === 200, `pick answers 200: ${res.status} ${res.body}`);
  return JSON.parse(res.body.toString("utf8"));
}

// The pixel of the full-size image under page point p.
async function pixelAt(page, options, p) {
  const r = await page.evaluate(() => document.getElementById("image").getBoundingClientRect().toJSON());
  return [Math.floor(((p.x - r.left) / r.width) * options.width), Math.floor(((p.y - r.top) / r.height) * options.height)];
}

// A point of the 3D image where the server's pick names `pointer`, near the world point `p`
// (searched over a few heights and offsets, since a model has holes): {page, pixel, hit}.
async function grabPoint(page, server, req, pointer, [x, y, z], height) {
  for (const dy of [0.5, 0.35, 0.65, 0.2, 0.8].map((f) => f * height)) {
    for (const [dx, dz] of [[0, 0], [0.15, 0], [-0.15, 0], [0, 0.15], [0, -0.15]]) {
      const at = await worldToPage(page, req.camera, req.options, [x + dx, y + dy, z + dz]);
      const pixel = await pixelAt(page, req.options, at);
      if (pixel[0] < 0 || pixel[1] < 0 || pixel[0] >= req.options.width || pixel[1] >= req.options.height) continue;
      const hit = await pick(server, { ...req, x: pixel[0], y: pixel[1] });
      if (hit.pointer === pointer) return { at, pixel, hit };
    }
  }
  return null;
}

// The id buffer of `req` as the CLI writes it: {width, height, at(x, y)}.
function cliIds(req) {
  const dir = path.join(outDir, "pieces");
  fs.mkdirSync(dir, { recursive: true });
  fs.writeFileSync(path.join(dir, "request.json"), JSON.stringify(req));
  execFileSync(path.resolve(binary), ["render", "request.json", "-o", "out.png", "--ids", "out.ids"], { cwd: dir, stdio: "ignore" });
  const bytes = fs.readFileSync(path.join(dir, "out.ids"));
  const width = bytes.readUInt32LE(0);
  const height = bytes.readUInt32LE(4);
  return { width, height, at: (x, y) => bytes.readUInt32LE(8 + 4 * (y * width + x)) };
}

// Every solid but the one at `index` is as it was: a piece moves whole, nothing else does.
function othersUnchanged(before, after, index) {
  return before.length === after.length && before.every((s, k) => k === index || JSON.stringify(s) === JSON.stringify(after[k]));
}

const scenarios = {
  async pieces_home({ page, server }) {
    await page.goto(`${server.url}/`);
    await designerReady(page);
    let seq = await renderSeq(page);
    await page.setInputFiles("#file", homeZip("3BedroomApartment"));
    await waitForNewRender(page, seq);
    const home = await request(page);
    // One piece per piece of furniture and lamp of the home (86 + 13 in its Home.xml).
    const pieces = home.scene.solids.filter((s) => s.type === "piece");
    assert(pieces.length === 99 && home.scene.solids.length === 99, `99 pieces: ${pieces.length} of ${home.scene.solids.length} solids`);
    const index = home.scene.solids.findIndex((s) => /^Sofa \(/.test(s.id || ""));
    const sofa = home.scene.solids[index];
    const pointer = `/scene/solids/${index}`;
    assert(sofa && sofa.parts.length >= 2, `the sofa is one piece of ${sofa?.parts.length} parts: ${sofa?.id}`);

    // Its warnings are listed under it, as one entry per piece (the home has at most 20).
    const listed = await page.$$eval("#warning-list > li.warning > button.pointer", (bs) => bs.map((b) => b.textContent));
    const summary = await page.textContent("#warnings-summary");
    assert(Number(summary.split(" ")[0]) <= 20 && listed.length >= 1 && new Set(listed).size === listed.length,
      `warnings, at most 20, one entry per element: ${summary}: ${listed}`);
    assert(await page.$('[data-testid="plan"] g.clash'), "a warning's pair is joined in the plan");

    // Drag it 1 m along x in the plan: the piece moves whole, one undo restores it.
    await page.click('button[data-tool="select"]');
    const from = [...sofa.center];
    assert(hitTest(home.scene, from, 0.05) === pointer, `the sofa is on top at its centre: ${hitTest(home.scene, from, 0.05)}`);
    seq = await renderSeq(page);
    await dragPlan(page, from, [from[0] + 1, from[1]], 10);
    await waitForNewRender(page, seq);
    let r = await request(page);
    assert(near(r.scene.solids[index].center, [from[0] + 1, from[1]], 0.051), `the plan drag moved the sofa 1 m: ${r.scene.solids[index].center}`);
    assert(othersUnchanged(home.scene.solids, r.scene.solids, index), "and nothing else");
    assert(JSON.stringify(r.scene.solids[index].parts) === JSON.stringify(sofa.parts), "its parts go with it");
    await page.keyboard.press("Control+z");
    r = await request(page);
    assert(near(r.scene.solids[index].center, from, 1e-9), `one undo puts it back: ${r.scene.solids[index].center}`);
    await idle(page);

    // Picking it on the image names the piece, and the part under the pointer as a detail.
    const grab = await grabPoint(page, server, r, pointer, [from[0], sofa.base ?? 0, from[1]], sofa.size[1]);
    assert(grab, "the sofa is seen in the image");
    assert(grab.hit.part && grab.hit.part.pointer.startsWith(`${pointer}/parts/`), `the pick names the part: ${JSON.stringify(grab.hit.part)}`);

    // Drag it 1 m on the 3D image: the grabbed point follows the pointer on its horizontal plane.
    const target = await worldToPage(page, r.camera, r.options, [grab.hit.point[0] + 1, grab.hit.point[1], grab.hit.point[2]]);
    seq = await renderSeq(page);
    await page.mouse.move(grab.at.x, grab.at.y);
    await page.mouse.down();
    await idle(page);  // the pick has answered: the sofa is grabbed
    assert(await hooks(page, "selection") === pointer, "pressing on the sofa selects it");
    for (let i = 1; i <= 10; i++) await page.mouse.move(grab.at.x + ((target.x - grab.at.x) * i) / 10, grab.at.y + ((target.y - grab.at.y) * i) / 10);
    await page.mouse.up();
    await waitForNewRender(page, seq);
    r = await request(page);
    assert(near(r.scene.solids[index].center, [from[0] + 1, from[1]], 0.08), `the image drag moved the sofa 1 m: ${r.scene.solids[index].center}`);
    assert(othersUnchanged(home.scene.solids, r.scene.solids, index), "and nothing else");
    assert(near(r.camera.position, home.camera.position), "the camera stayed");
    // Where it went, the image shows it: a pick there names it.
    const moved = await pick(server, { ...r, x: (await pixelAt(page, r.options, target))[0], y: (await pixelAt(page, r.options, target))[1] });
    assert(moved.pointer === pointer, `the sofa is drawn where it was dropped: ${moved.pointer}`);
    await page.keyboard.press("Control+z");
    r = await request(page);
    assert(near(r.scene.solids[index].center, from, 1e-9), `one undo puts it back: ${r.scene.solids[index].center}`);

    // R turns it 15° (one step), M mirrors it, Delete removes it whole.
    await page.focus('[data-testid="plan"]');
    await page.keyboard.press("r");
    r = await request(page);
    assert(r.scene.solids[index].rotation_y === ((sofa.rotation_y ?? 0) + 15 + 360) % 360, `R turned it: ${r.scene.solids[index].rotation_y}`);
    await page.keyboard.press("m");
    r = await request(page);
    assert(r.scene.solids[index].mirrored === true && othersUnchanged(home.scene.solids, r.scene.solids, index), "M mirrored it");
    await page.keyboard.press("Control+z");
    await page.keyboard.press("Control+z");
    assert(JSON.stringify((await request(page)).scene.solids[index]) === JSON.stringify(sofa), "two undos restore it");
    seq = await renderSeq(page);
    await page.keyboard.press("Delete");
    await waitForNewRender(page, seq);
    r = await request(page);
    assert(r.scene.solids.length === 98 && !r.scene.solids.some((s) => s.id === sofa.id), "Delete took the sofa away whole");
    const gone = await pick(server, { ...r, x: grab.pixel[0], y: grab.pixel[1] });
    assert(gone.pointer !== pointer && !(gone.part?.pointer || "").startsWith(`${pointer}/`), `nothing of it is left where it was: ${gone.pointer}`);
  },

  async pieces_catalogue({ page, server, context }) {
    await openEmpty(page, server);
    await drawRoom(page);
    await idle(page);
    const room = await imageSummary(page);
    const catalogue = JSON.parse((await httpRequest(`${server.url}/v1/catalogue`)).body.toString("utf8"));
    const chair = catalogue.items.find((i) => i.id === "chair");
    assert(chair && chair.category === "Living room", "the catalogue has Sweet Home 3D's chair");

    // The catalogue shows icons by category; the chair's button names it with its real size.
    await page.click('button[data-tool="furniture"]');
    await page.selectOption("#catalogue-category", "Living room");
    const title = await page.getAttribute('#catalogue-items [data-item="chair"]', "title");
    assert(/Chair, 40 × 42 cm, 90 cm high/.test(title), `the button says what it is: ${title}`);
    // With its icon, once the image has loaded (GET /v1/catalogue/chair/icon.png).
    const icon = await page.waitForFunction(() => {
      const img = document.querySelector('#catalogue-items [data-item="chair"] img');
      return img && img.complete && img.naturalWidth > 0;
    }, null, { timeout: 10000 }).then(() => true, () => false);
    assert(icon, "with its icon");
    let seq = await renderSeq(page);
    await page.click('#catalogue-items [data-item="chair"]');
    await clickPlan(page, 2.5, 1);
    await waitForNewRender(page, seq);
    let r = await request(page);
    const placed = r.scene.solids[0];
    assert(r.scene.solids.length === 1 && placed.type === "piece" && near(placed.center, [2.5, 1]) && near(placed.size, [0.4, 0.9, 0.42]),
      `a chair piece at (2.5, 1), 40 × 90 × 42 cm: ${JSON.stringify({ ...placed, parts: placed.parts.length })}`);
    assert(JSON.stringify(placed.parts) === JSON.stringify(chair.piece.parts), "its parts are the catalogue's");

    // Look at it as a visitor: K (the visitor starts in the room, under the plan's centre, facing
    // north as the camera did), a step of 1 m back, Escape.
    await page.click('button[data-tool="walk"]');
    await page.waitForFunction(() => window.roomrenderDesigner.request().camera.position[1] === 1.6);
    await page.keyboard.press("Shift+ArrowDown");
    await page.keyboard.press("Escape");
    await idle(page);
    r = await request(page);
    assert(r.camera.position[2] > 2 && r.camera.position[2] < 4, `inside the room: ${r.camera.position}`);
    const shown = await imageSummary(page);
    assert(shown.hash !== room.hash, "the image changed");

    // Its real shape: in the id buffer, the chair covers well under the area of a box of its size
    // seen from the same place (the gaps of its back and between its legs show what is behind).
    const wallPolygons = JSON.parse((await httpRequest(`${server.url}/v1/render`, {
      method: "POST", headers: { "Content-Type": "application/json", Accept: "application/json" },
      body: JSON.stringify({ ...r, scene: { ...r.scene, solids: [] } }),
    })).body.toString("utf8")).counts.polygons;
    const covered = (ids) => {
      let n = 0;
      for (let y = 0; y < ids.height; y++) for (let x = 0; x < ids.width; x++) if (ids.at(x, y) !== 0xffffffff && ids.at(x, y) >= wallPolygons) n++;
      return n;
    };
    const { parts: _parts, type: _type, ...placement } = placed;
    const chairPixels = covered(cliIds(r));
    const boxPixels = covered(cliIds({ ...r, scene: { ...r.scene, solids: [{ ...placement, type: "box" }] } }));
    assert(chairPixels > 2000 && chairPixels < 0.8 * boxPixels, `the chair is its model, not its box: ${chairPixels} of ${boxPixels} pixels`);
    const ids = cliIds(r);
    let middle = null;
    for (let y = 0; y < ids.height && !middle; y += 4) {
      for (let x = 0; x < ids.width; x += 4) {
        if (ids.at(x, y) !== 0xffffffff && ids.at(x, y) >= wallPolygons) middle = [x, y];
      }
    }
    const hit = await pick(server, { ...r, x: middle[0], y: middle[1] });
    assert(hit.pointer === "/scene/solids/0" && hit.part?.pointer.startsWith("/scene/solids/0/parts/"), `a pick names the piece and its part: ${JSON.stringify(hit)}`);

    // Saved, its permalink reloads the same request and the same image.
    await page.click('[data-action="save"]');
    await page.waitForSelector("#share-links:not([hidden])");
    const link = await page.getAttribute("#permalink", "href");
    const png = await hooks(page, "png");
    const other = await context.newPage();
    await other.goto(link);
    await designerReady(other);
    const reloaded = await request(other);
    assert(JSON.stringify(reloaded.scene.solids[0].parts) === JSON.stringify(placed.parts) && near(reloaded.scene.solids[0].center, [2.5, 1]),
      "the permalink gives the chair back");
    assert(await hooks(other, "png") === png, "and the same PNG bytes");
    await other.close();
  },

  // A catalogue sofa resized with its corner handle in the plan: width and depth follow the pointer,
  // the opposite corner stays, the image follows; one undo restores it; with Shift held the three
  // sides keep their proportions.
  async pieces_resize({ page, server }) {
    await openEmpty(page, server);
    await drawRoom(page);
    await idle(page);
    let seq = await renderSeq(page);
    await chooseItem(page, "Living room", "sofa");
    await clickPlan(page, 2.5, 2);
    await waitForNewRender(page, seq);
    await page.click('button[data-tool="select"]');
    await clickPlan(page, 2.5, 2);
    await idle(page);
    const pointer = "/scene/solids/0";
    assert(await hooks(page, "selection") === pointer, `the sofa is selected: ${await hooks(page, "selection")}`);
    const sofa = (await request(page)).scene.solids[0];
    assert(near(sofa.size, [1.47, 0.87, 0.87]) && near(sofa.center, [2.5, 2]), `Sweet Home 3D's sofa, 147 × 87 × 87 cm: ${JSON.stringify(sofa.size)}`);
    assert(await page.$$eval('[data-testid="plan"] .handle.resize', (hs) => hs.length) === 4, "four corner handles in the plan");
    const shown = await imageSummary(page);

    // The corner at +x +z dragged 0.5 m along x: 1.97 m wide, the same depth, the centre 0.25 m on.
    const corner = [2.5 + 0.735, 2 + 0.435];
    seq = await renderSeq(page);
    await dragPlan(page, corner, [corner[0] + 0.5, corner[1]], 10);
    await waitForNewRender(page, seq);
    let r = await request(page);
    let s = r.scene.solids[0];
    // Within a pointer pixel (the plan shows about 2 cm a pixel here) and the whole centimetres sizes
    // are rounded to; the opposite corner exactly where it was (to the millimetre centres are kept to).
    assert(near(s.size, [1.97, 0.87, 0.87], 0.021) && s.size[2] === 0.87, `resized: ${JSON.stringify({ size: s.size, center: s.center })}`);
    assert(near(resizeHandles(s)[0], resizeHandles(sofa)[0], 0.0011), `the opposite corner stays: ${resizeHandles(s)[0]} ${resizeHandles(sofa)[0]}`);
    assert(JSON.stringify(s.parts) === JSON.stringify(sofa.parts), "its parts stay the model's");
    assert((await imageSummary(page)).hash !== shown.hash, "the image shows the wider sofa");
    await page.keyboard.press("Control+z");
    r = await request(page);
    assert(near(r.scene.solids[0].size, sofa.size) && near(r.scene.solids[0].center, sofa.center), "one undo restores it");
    await idle(page);

    // With Shift: 0.5 m along x reaches (0.5 · 1.47) / (1.47² + 0.87²) ≈ 0.252 of the diagonal more.
    seq = await renderSeq(page);
    await page.keyboard.down("Shift");
    await dragPlan(page, corner, [corner[0] + 0.5, corner[1]], 10);
    await page.keyboard.up("Shift");
    await waitForNewRender(page, seq);
    s = (await request(page)).scene.solids[0];
    const g = 1 + (0.5 * 1.47) / (1.47 ** 2 + 0.87 ** 2);
    const expected = sofa.size.map((v) => v * g);
    assert(near(s.size, expected, 0.021), `the proportions are kept: ${JSON.stringify(s.size)} against ${JSON.stringify(expected)}`);
    assert(Math.abs(s.size[0] / s.size[2] - 1.47 / 0.87) < 0.03 && Math.abs(s.size[1] / s.size[2] - 1) < 0.03, `width : depth : height as before: ${JSON.stringify(s.size)}`);
  },
};

const prechecks = {
  async pieces_home(server) {
    await requireHome(server, "3BedroomApartment");
    if (!(await serverHas(server, "/v1/pick"))) skip("needs POST /v1/pick");
  },
  async pieces_catalogue(server) {
    if (!(await serverHas(server, "/v1/catalogue", "get"))) skip("needs GET /v1/catalogue");
  },
};

const body = scenarios[scenario];
if (!binary || !outDir || !body) {
  console.error(`usage: pieces.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")})`);
  process.exit(2);
}
process.exit(await runScenario(scenario, { binary, outDir, precheck: prechecks[scenario] }, body));
