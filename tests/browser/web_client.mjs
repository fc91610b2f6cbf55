// The web client in real Chromium against the real server: each scenario is one CTest test.
//   node tests/browser/web_client.mjs BUILD/roomrender OUT_DIR SCENARIO
//   node tests/browser/web_client.mjs BUILD/roomrender OUT_DIR --screenshot docs/images/web-client.png
// A scenario that needs an endpoint the server lacks exits 77 (CTest: skipped) naming it. What a
// person sees is what is checked: the image's pixels, the bars of the chart, the messages at the
// fields, the files the download buttons save.
import fs from "node:fs";
import { runScenario, serverHas, httpRequest, skip, assert, repoRoot, imageSummary, renderSeq, waitForRender } from "./support.mjs";

const [binary, outDir, scenario, screenshotPath] = process.argv.slice(2);

// ---- page helpers ---------------------------------------------------------------------------

async function open(page, server, example) {
  await page.goto(`${server.url}/`);
  let seq = await waitForRender(page, 0);
  if (example) {
    await page.selectOption("#example", example);
    seq = await waitForRender(page, seq);
  }
  return seq;
}

async function download(page, button) {
  const [file] = await Promise.all([page.waitForEvent("download"), page.click(button)]);
  return fs.readFileSync(await file.path());
}

// The request as the page holds it, through the "Scene" download button.
async function requestInPage(page) {
  return JSON.parse((await download(page, "#download-scene")).toString("utf8"));
}

// Replaces the editor's text as a paste would.
async function pasteRequest(page, text) {
  await page.click(".cm-content");
  await page.keyboard.press("Control+A");
  await page.keyboard.insertText(text);
}

const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);

function pngSize(buffer) {
  assert(buffer.subarray(0, 8).equals(Buffer.from([137, 80, 78, 71, 13, 10, 26, 10])), "the download is a PNG");
  return { width: buffer.readUInt32BE(16), height: buffer.readUInt32BE(20) };
}

// Lines of the editor that carry an inline message of `kind` (error or warning), with its text.
function inlineMessages(page, kind) {
  return page.$$eval(`.cm-line:has(.cm-inline-${kind})`, (lines, k) => lines.map((l) => ({
    line: l.textContent.replace(l.querySelector(`.cm-inline-${k}`).textContent, ""),
    message: l.querySelector(`.cm-inline-${k}`).textContent,
  })), kind);
}

// ---- scenarios ------------------------------------------------------------------------------

const scenarios = {
  // Pick an example, see the image and the timings; drag, scroll and use keys to move the camera,
  // and see each move produce a new image: while dragging, one render at a time, none cancelled, and
  // the request text untouched until the camera rests.
  async render_and_orbit({ page, server }) {
    let seq = await open(page, server, "studio");
    const studio = JSON.parse(fs.readFileSync(`${repoRoot}/examples/studio.json`, "utf8"));
    const loaded = await requestInPage(page);
    assert(JSON.stringify(loaded) === JSON.stringify(studio), "the editor holds examples/studio.json");
    const first = await imageSummary(page, "#image");
    assert(first.width === 640 && first.height === 480, `image is 640x480, got ${first.width}x${first.height}`);
    assert(first.colours > 20, `the image shows a room (${first.colours} colours)`);
    const bars = await page.$$eval("#timings rect.bar", (rs) => rs.map((r) => ({ stage: r.dataset.stage, ms: Number(r.dataset.ms) })));
    assert(bars.length >= 3 && bars.every((b) => Number.isFinite(b.ms) && b.ms >= 0), `timing bars: ${JSON.stringify(bars)}`);
    assert(bars.some((b) => b.stage === "raster" && b.ms > 0), "the chart has a raster bar");
    assert(/Rendered in/.test(await page.textContent("#status")), "the status says it rendered");

    // Drag to orbit. The camera moves in the page, not in the text, and each image is the stored
    // scene seen from it (POST /v1/scenes/{id}/render). The first image of the drag is held back by
    // the network for 0.6 s: the page keeps it (no second image of the drag is asked for meanwhile),
    // shows it, then asks for the newest camera.
    const textBefore = await page.evaluate(() => window.roomrenderDesigner.text());
    const views = [];  // {request, done, failed} of each POST /v1/scenes/{id}/render
    const small = (v) => JSON.parse(v.request.postData()).options.width === 320;
    let overlapping = 0;  // reduced-size renders asked for while another was on its way
    page.on("request", (r) => {
      if (r.method() !== "POST" || !/\/v1\/scenes\/[0-9a-f]+\/render$/.test(r.url())) return;
      const view = { request: r };
      if (small(view) && views.some((v) => small(v) && !v.done && !v.failed)) overlapping++;
      views.push(view);
    });
    page.on("requestfinished", (r) => { const v = views.find((x) => x.request === r); if (v) v.done = true; });
    page.on("requestfailed", (r) => { const v = views.find((x) => x.request === r); if (v) v.failed = true; });
    let held = null;
    let heldSeen = -1;  // views asked for while the held one was on its way
    await page.route("**/v1/scenes/*/render", async (route) => {
      if (held) return route.continue();
      held = route.request();
      await new Promise((r) => setTimeout(r, 600));
      heldSeen = views.length;
      await route.continue().catch(() => {});
    });
    const box = await page.locator("#image").boundingBox();
    const [cx, cy] = [box.x + box.width / 2, box.y + box.height / 2];
    await page.mouse.move(cx, cy);
    await page.mouse.down();
    let textDuring = null;
    for (let i = 1; i <= 10; i++) {
      await page.mouse.move(cx + 15 * i, cy + 4 * i);
      await page.waitForTimeout(150);
      if (i === 5) textDuring = await page.evaluate(() => window.roomrenderDesigner.text());
    }
    assert(textDuring === textBefore, "the request text stays as it was while the camera moves");
    await page.mouse.up();
    seq = await waitForRender(page, seq);
    await page.unroute("**/v1/scenes/*/render");
    assert(held, "the drag rendered the stored scene by id");
    assert(heldSeen === 1, `no other image was asked for while the first was on its way (${heldSeen} asked)`);
    assert(!views.find((v) => v.request === held).failed, "the image in flight was not cancelled by the drag's next moves");
    const dragViews = views.filter(small);
    assert(dragViews.length >= 2, `the drag showed more than the held image: ${dragViews.length} reduced-size renders`);
    assert(overlapping === 0, `one drag render at a time (${overlapping} asked for while another was on its way)`);
    // The image on screen is the final camera's, as the server draws that request inline.
    const final = await page.evaluate(() => window.roomrenderDesigner.request());
    const inline = await httpRequest(`${server.url}/v1/render`, { method: "POST", headers: { "Content-Type": "application/json" },
      body: JSON.stringify(final) });
    const shownPng = Buffer.from(await page.evaluate(() => window.roomrenderDesigner.png()), "base64");
    assert(inline.status === 200 && inline.body.equals(shownPng), "the image shown is the final camera's, byte for byte");
    // The text catches up once the page rests, or at once when the editor is opened.
    await page.waitForFunction((t) => window.roomrenderDesigner.text() !== t, textBefore, { timeout: 5000 });
    const written = JSON.parse(await page.evaluate(() => window.roomrenderDesigner.text())).camera;
    assert(JSON.stringify(written) === JSON.stringify(final.camera), "the text holds the camera shown once the page rests");
    const orbited = await requestInPage(page);
    assert(distance(orbited.camera.position, studio.camera.position) > 0.5, "dragging moved the camera");
    assert(JSON.stringify(orbited.camera.target) === JSON.stringify(studio.camera.target), "orbiting kept the target");
    const r0 = distance(studio.camera.position, studio.camera.target);
    assert(Math.abs(distance(orbited.camera.position, orbited.camera.target) - r0) < 0.01, "orbiting kept the distance");
    assert(JSON.stringify(orbited.scene) === JSON.stringify(studio.scene), "orbiting left the scene alone");
    const second = await imageSummary(page, "#image");
    assert(second.hash !== first.hash, "the new render shows a different image");

    // Scroll to zoom in, arrow key to orbit, 0 to return to the example's camera.
    seq = await renderSeq(page);
    await page.mouse.move(cx, cy);
    await page.mouse.wheel(0, -300);
    seq = await waitForRender(page, seq);
    const zoomed = await requestInPage(page);
    assert(distance(zoomed.camera.position, zoomed.camera.target) < r0 - 0.1, "scrolling up zoomed in");
    await page.focus("#views");
    await page.keyboard.press("ArrowLeft");
    seq = await waitForRender(page, seq);
    const turned = await requestInPage(page);
    assert(distance(turned.camera.position, zoomed.camera.position) > 0.05, "the arrow key orbited");
    await page.focus("#views");  // the download button took the focus
    await page.keyboard.press("0");
    seq = await waitForRender(page, seq);
    assert(JSON.stringify((await requestInPage(page)).camera) === JSON.stringify(studio.camera), "0 restored the camera");
    assert((await imageSummary(page, "#image")).hash === first.hash, "the same camera gives the same image again");

    const png = pngSize(await download(page, "#download-png"));
    assert(png.width === 640 && png.height === 480, "the PNG download is the rendered image");
  },

  // Server errors (422 with a JSON Pointer) appear at the field; fixing the field clears them.
  async field_errors({ page, server }) {
    let seq = await open(page, server, "studio");
    const request = await requestInPage(page);
    // JSON that does not parse is marked in the editor and not sent.
    await pasteRequest(page, '{"camera": {"fov_y": }}');
    await page.waitForSelector(".cm-inline-error");
    await page.click("#render");
    await page.waitForFunction(() => /not valid JSON/.test(document.getElementById("problems").textContent));
    // near > far passes the schema; only the server can tell, and it names /camera/far.
    request.camera.near = 50;
    request.camera.far = 10;
    await pasteRequest(page, JSON.stringify(request, null, 2));
    await page.keyboard.press("Control+Enter");
    await page.waitForSelector("#problems li .pointer");
    const problem = await page.textContent("#problems li");
    assert(problem.includes("/camera/far") && problem.includes("greater than 50"), `problem listed: ${problem}`);
    await page.click("#problems li .pointer");  // shows the field in the editor, selected
    await page.waitForSelector(".cm-lintRange-error");
    const marked = await page.$$eval(".cm-lintRange-error", (els) => els.map((e) => e.textContent));
    assert(marked.includes("10"), `the value of far is underlined: ${JSON.stringify(marked)}`);
    const messages = await inlineMessages(page, "error");
    assert(messages.some((m) => m.line.includes('"far": 10') && m.message.includes("greater than 50")),
      `the message sits on far's line: ${JSON.stringify(messages)}`);
    assert(await renderSeq(page) === seq, "the refused request did not replace the image");
    // Typing over the selected value fixes it: the message goes, and the render goes through.
    await page.keyboard.type("80");
    await page.waitForFunction(() => !document.querySelector(".cm-inline-error"));
    await page.keyboard.press("Control+Enter");
    seq = await waitForRender(page, seq);
    assert((await requestInPage(page)).camera.far === 80, "the edit went into the request");
    assert((await page.$$("#problems li.error")).length === 0, "no errors left (placement warnings may stay)");
  },

  // Two pipelines side by side: against itself a pipeline differs nowhere; on intersecting
  // triangles the painter's order is wrong where they cross, so its image differs from the z-buffer's.
  async compare({ page, server }) {
    let seq = await open(page, server, "tri_intersecting");
    await page.check("#compare");
    await page.selectOption("#pipeline-b", "zbuffer");
    seq = await waitForRender(page, seq);
    const metrics = async () => ({ share: Number(await page.getAttribute("#metrics", "data-share")),
      psnr: Number(await page.getAttribute("#metrics", "data-psnr")), text: await page.textContent("#metrics") });
    const same = await metrics();
    assert(same.share === 0 && same.psnr === Infinity && same.text.includes("∞"), `zbuffer against itself: ${same.text}`);
    const bars = await page.$$eval("#timings rect.bar", (rs) => rs.map((r) => r.dataset.series));
    assert(bars.length > 0 && bars.length % 2 === 0, "the timing chart has a bar per stage for each render");
    const pipelines = await page.$$eval("#pipeline option", (os) => os.map((o) => o.value));
    if (!pipelines.includes("painter")) skip("needs the painter pipeline in GET /v1/pipelines to show a difference");
    await page.selectOption("#pipeline", "painter");
    seq = await waitForRender(page, seq);
    const a = await imageSummary(page, "#image");
    const b = await imageSummary(page, "#image-b");
    assert(a.width === b.width && a.height === b.height, "both images have the request's size");
    assert(a.hash !== b.hash, "painter and zbuffer images differ on intersecting triangles");
    const diff = await page.$eval("#diff", (c) => ({ width: c.width, height: c.height }));
    assert(diff.width === a.width && diff.height === a.height, "the difference image has the same size");
    // On screen too, the two images and their difference show at one size.
    const boxes = await Promise.all(["#image", "#image-b", "#diff"].map((sel) => page.locator(sel).boundingBox()));
    assert(boxes.every((b) => Math.abs(b.width - boxes[0].width) < 1 && Math.abs(b.height - boxes[0].height) < 1),
      `the images show at one size: ${JSON.stringify(boxes.map((b) => [Math.round(b.width), Math.round(b.height)]))}`);
    const differ = await metrics();
    assert(differ.share > 0 && differ.share < 0.5, `a small share of pixels differs: ${differ.share}`);
    assert(Number.isFinite(differ.psnr) && differ.psnr > 5, `PSNR is finite: ${differ.psnr}`);
  },

  // Schema errors show at the field while typing, before anything is sent.
  async schema_as_you_type({ page, server }) {
    await open(page, server, "studio");
    const request = await requestInPage(page);
    assert((await page.textContent("#check-note")).includes("schema"), "the page says it checks as you type");
    let renders = 0;
    page.on("request", (r) => { if (r.url().endsWith("/v1/render")) renders += 1; });
    request.camera.fov_y = 500;
    await pasteRequest(page, JSON.stringify(request, null, 2));
    await page.waitForSelector(".cm-lint-marker-error");
    await page.keyboard.press("Control+Home");
    // F8 goes to the next problem and scrolls to it (past any placement warning from the last render).
    for (let i = 0; i < 5 && !(await page.$(".cm-lintRange-error")); i++) {
      await page.keyboard.press("F8");
      await page.waitForTimeout(100);
    }
    const marked = await page.$$eval(".cm-lintRange-error", (els) => els.map((e) => e.textContent));
    assert(marked.includes("500"), `fov_y's value is underlined: ${JSON.stringify(marked)}`);
    const messages = await inlineMessages(page, "error");
    assert(messages.some((m) => m.line.includes('"fov_y": 500') && m.message.includes("170")),
      `the schema's message sits on fov_y's line: ${JSON.stringify(messages)}`);
    assert(renders === 0, "nothing was sent to the server");
  },

  // JSON answers carry counts and placement warnings; warnings appear at the solid that causes them.
  async json_answers({ page, server }) {
    let seq = await open(page, server, "studio");
    const request = await requestInPage(page);
    request.scene.solids.push({ type: "box", id: "through_the_wall", center: [3, 0], size: [1, 1, 1], color: "#ff0000" });
    await pasteRequest(page, JSON.stringify(request, null, 2));
    await page.keyboard.press("Control+Enter");
    seq = await waitForRender(page, seq);
    const stats = await page.textContent("#stats");
    assert(/polygons\s*\d+/.test(stats), `the stats show polygon counts: ${stats}`);
    const index = request.scene.solids.length - 1;
    const warning = await page.textContent("#warning-list li.warning");
    assert(warning.includes(`/scene/solids/${index}`), `a placement warning names the box: ${warning}`);
    await page.click("#warning-list li.warning .pointer");
    await page.waitForSelector(".cm-inline-warning");
  },

  // Server notes that arrive after the editor's last lint run (a slow server; here the page's render
  // answer is held back 1.5 s, well past the 250 ms lint delay) are drawn at once, with no keystroke.
  async late_server_notes({ page, server }) {
    let seq = await open(page, server, "studio");
    const request = await requestInPage(page);
    request.scene.solids.push({ type: "box", id: "through_the_wall", center: [3, 0], size: [1, 1, 1], color: "#ff0000" });
    await pasteRequest(page, JSON.stringify(request, null, 2));
    let held = 0;
    await page.route("**/v1/render", async (route) => {
      const response = await route.fetch();
      held += 1;
      await new Promise((done) => setTimeout(done, 1500));
      await route.fulfill({ response });
    });
    await page.keyboard.press("Control+Enter");
    seq = await waitForRender(page, seq);
    assert(held >= 1, "the render answer was held back");
    const pointer = `/scene/solids/${request.scene.solids.length - 1}`;
    // The list has one entry per element, its button named after the element, its warnings under it.
    const item = await page.$(`#warning-list li.warning:has(.pointer[title^="${pointer}:"])`);
    assert(item, `a placement warning names the box (${pointer})`);
    const detail = (await item.$eval("ul > li", (li) => li.textContent)).trim();
    await item.$eval(".pointer", (b) => b.click());  // scrolls the editor to the box; edits nothing
    const shown = await page.waitForFunction((d) => [...document.querySelectorAll(".cm-inline-warning")]
      .some((e) => e.textContent.includes(d)), detail, { timeout: 5000 }).then(() => true, () => false);
    assert(shown, `the box's warning is written at its line without a keystroke: ${detail}`);
  },

  // A Sweet Home 3D file goes through the server's importer into the editor, and renders.
  async import_file({ page, server }) {
    let seq = await open(page, server);
    await page.setInputFiles("#file", `${repoRoot}/tests/clients/fixtures/two_rooms.xml`);
    seq = await waitForRender(page, seq);
    const request = await requestInPage(page);
    assert(request.scene.walls.length === 5, `the home's five walls were imported: ${request.scene.walls.length}`);
    assert(request.scene.walls.some((w) => (w.openings || []).some((o) => o.type === "door")), "with its door");
    // A home opens with Phong and exact shadows: this one has no lamp and its ceiling keeps the sun
    // out, so its walls, floor and furniture show in a few flat ambient colours.
    const shown = await imageSummary(page, "#image");
    assert(shown.colours >= 3, `and rendered: ${shown.colours} colours`);
  },

  // A narrow window shows the image on its first screen; a wide one keeps the toolbar to one row.
  async layout_widths({ page, server }) {
    await page.setViewportSize({ width: 800, height: 900 });
    await open(page, server);
    const image = await page.locator("#image").boundingBox();
    assert(image && image.y >= 0 && image.y < 900 && image.height > 100, `at 800x900 the image starts on screen: ${JSON.stringify(image)}`);
    await page.setViewportSize({ width: 1440, height: 900 });
    // One row: every item starts above the bottom of the one that ends highest.
    const toolbar = await page.$$eval('.toolbar[aria-label="Render settings"] > :not([hidden])', (items) => {
      const rects = items.map((e) => e.getBoundingClientRect()).filter((r) => r.width > 0);
      const bottom = Math.min(...rects.map((r) => r.bottom));
      return { oneRow: rects.every((r) => r.top < bottom), items: rects.map((r) => [Math.round(r.top), Math.round(r.right)]) };
    });
    assert(toolbar.oneRow, `at 1440 px the toolbar is one row: ${JSON.stringify(toolbar.items)}`);
  },
};

// Endpoints a scenario needs beyond the first server's, checked before the browser starts.
const prechecks = {
  async schema_as_you_type(server) {
    if (!(await serverHas(server, "/v1/schemas/{name}.json", "get"))) {
      skip("needs GET /v1/schemas/{name}.json (the issue-5 server) to check requests as they are typed");
    }
  },
  async json_answers(server) {
    const res = await httpRequest(`${server.url}/v1/render`, { method: "POST", body: "{}",
      headers: { "Content-Type": "application/json", "Content-Length": "2", Accept: "application/json" } });
    if (!(res.headers["content-type"] || "").startsWith("application/json")) {
      skip("needs JSON answers from POST /v1/render with Accept: application/json (the issue-5 server)");
    }
  },
  async import_file(server) {
    if (!(await serverHas(server, "/v1/import/{format}"))) {
      skip("needs POST /v1/import/{format} (the importers' endpoint) to import a Sweet Home 3D home");
    }
  },
};

// The picture of the page for docs/images (not a test).
async function screenshot({ page, server }) {
  await open(page, server, "apartment");
  await page.screenshot({ path: screenshotPath });
  console.log(`wrote ${screenshotPath}`);
}

const body = scenario === "--screenshot" ? screenshot : scenarios[scenario];
if (!binary || !outDir || !body) {
  console.error(`usage: web_client.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")}|--screenshot FILE)`);
  process.exit(2);
}
process.exit(await runScenario(scenario.replace(/^--/, ""), { binary, outDir, precheck: prechecks[scenario] }, body));
