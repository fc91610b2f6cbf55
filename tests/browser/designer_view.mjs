// The designer's 3D image in real Chromium against the real server, mouse and keyboard only: a click
// selects what the id buffer shows there (the expected element comes from `roomrender render --ids`
// and the service's pick, never from a table here), a drag on a chair moves it on the floor with
// reduced-size renders on the way, the anti-aliasing control sets options.antialias in what is
// sent, and "Frame all" shows the camera the service frames with "camera": {"frame": "all"}.
//   node tests/browser/designer_view.mjs BUILD/roomrender OUT_DIR SCENARIO
import { runScenario, assert, httpRequest, serverHas, skip } from "./support.mjs";
import { hooks, idle, request, near, clickPlan, openEmpty, worldToPage, chooseItem, designerReady } from "./designer_support.mjs";
import { execFileSync } from "node:child_process";
import fs from "node:fs";
import path from "node:path";

const [binary, outDir, scenario] = process.argv.slice(2);

async function pick(server, body) {
  const res = await httpRequest(`${server.url}/v1/pick`, {
    method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(body),
  });
  assert(res.status === 200, `pick answers 200: ${res.status} ${res.body}`);
  return JSON.parse(res.body.toString("utf8"));
}

// The id buffer of `req` as the CLI writes it: {width, height, at(x, y)}.
function cliIds(req) {
  const dir = path.join(outDir, "designer_view");
  fs.mkdirSync(dir, { recursive: true });
  fs.writeFileSync(path.join(dir, "request.json"), JSON.stringify(req));
  execFileSync(path.resolve(binary), ["render", "request.json", "-o", "out.png", "--ids", "out.ids"], { cwd: dir, stdio: "ignore" });
  const bytes = fs.readFileSync(path.join(dir, "out.ids"));
  const width = bytes.readUInt32LE(0);
  const height = bytes.readUInt32LE(4);
  return { width, height, at: (x, y) => bytes.readUInt32LE(8 + 4 * (y * width + x)) };
}

// One pixel inside each region of the id buffer (its four neighbours show the same polygon), the
// largest regions first.
function regionPixels(ids) {
  const found = new Map();
  for (let y = 1; y + 1 < ids.height; y += 2) {
    for (let x = 1; x + 1 < ids.width; x += 2) {
      const id = ids.at(x, y);
      if (id === 0xffffffff || [ids.at(x - 1, y), ids.at(x + 1, y), ids.at(x, y - 1), ids.at(x, y + 1)].some((n) => n !== id)) continue;
      const entry = found.get(id) || { id, count: 0, pixels: [] };
      entry.count++;
      entry.pixels.push([x, y]);
      found.set(id, entry);
    }
  }
  return [...found.values()].sort((a, b) => b.count - a.count)
    .map((e) => ({ id: e.id, pixel: e.pixels[Math.floor(e.pixels.length / 2)] }));
}

async function openApartment(page, server) {
  if (!(await serverHas(server, "/v1/pick"))) skip("the server has no POST /v1/pick");
  await page.goto(`${server.url}/`);
  await designerReady(page);
}

const scenarios = {
  // Clicks on pixels of the apartment select the element there: the service's pick names the
  // polygon the CLI's id buffer holds at that pixel, and the page selects the element it names.
  async designer_pick({ page, server }) {
    await openApartment(page, server);
    const req = await request(page);
    const ids = cliIds(req);
    assert(ids.width === req.options.width && ids.height === req.options.height, `id buffer ${ids.width}×${ids.height}`);
    const kinds = new Set();
    let clicks = 0;
    for (const { id, pixel: [x, y] } of regionPixels(ids).slice(0, 40)) {
      const answer = await pick(server, { ...req, x, y });
      assert(answer.polygon === id, `the service picks the id buffer's polygon at ${x},${y}: ${answer.polygon} vs ${id}`);
      const kind = /^\/scene\/(floor|walls|solids|rooms)/.exec(answer.pointer)?.[1];
      if (!kind || kinds.has(kind)) continue;
      kinds.add(kind);
      const p = await hooks(page, "viewToPage", x, y);
      await page.mouse.click(p.x, p.y);
      await idle(page);
      const selected = await hooks(page, "selection");
      assert(selected === answer.pointer, `a click on pixel ${x},${y} selects ${answer.pointer}: ${selected}`);
      clicks++;
    }
    assert(kinds.has("solids") && kinds.has("walls") && clicks >= 2, `clicked a solid and a wall: ${[...kinds]}`);
    // The background selects nothing.
    assert(ids.at(0, 0) === 0xffffffff, "the top-left pixel is background");
    const corner = await hooks(page, "viewToPage", 0, 0);
    await page.mouse.click(corner.x, corner.y);
    await idle(page);
    assert(await hooks(page, "selection") === null, "a click on the background clears the selection");
    assert(near((await request(page)).camera.position, req.camera.position), "clicks do not move the camera");
  },

  // A drag that starts on the chair in the image moves it on the floor: the point grabbed follows
  // the pointer; half-size renders while dragging, then the edited request in full.
  async designer_view_drag({ page, server }) {
    if (!(await serverHas(server, "/v1/pick"))) skip("the server has no POST /v1/pick");
    await openEmpty(page, server);
    await chooseItem(page, "Living room", "chair");
    await clickPlan(page, 2, 2);
    await page.click('button[data-tool="select"]');
    await idle(page);
    const before = await request(page);
    const full = { width: before.options.width, height: before.options.height };
    // The seat's centre, and the point the service finds there (on the seat or the back in front of it).
    const a = await worldToPage(page, before.camera, full, [2, 0.45, 2]);
    const grabbed = await page.evaluate(({ x, y }) => document.elementFromPoint(x, y)?.dataset.testid, a);
    assert(grabbed === "view", `the chair's seat is on the image: ${grabbed}`);
    const r = await page.evaluate(() => document.getElementById("image").getBoundingClientRect());
    const pixel = [Math.floor(((a.x - r.left) / r.width) * full.width), Math.floor(((a.y - r.top) / r.height) * full.height)];
    const hit = await pick(server, { ...before, x: pixel[0], y: pixel[1] });
    assert(hit.pointer === "/scene/solids/0", `the service picks the chair there: ${hit.pointer}`);
    const b = await worldToPage(page, before.camera, full, [hit.point[0] + 1, hit.point[1], hit.point[2] + 0.5]);

    const sent = [];
    const isRender = (r) => r.url().endsWith("/v1/render");
    page.on("request", (r) => {
      if (isRender(r)) sent.push(JSON.parse(r.postData()));
    });
    const preview = page.waitForRequest((r) => isRender(r) && JSON.parse(r.postData()).options?.width === full.width / 2 &&
      JSON.parse(r.postData()).scene.solids[0].center[0] > 2.2);
    await page.mouse.move(a.x, a.y);
    await page.mouse.down();
    await idle(page);  // the pick has answered: the chair is what was grabbed
    assert(await hooks(page, "selection") === "/scene/solids/0", "pressing on the chair selects it");
    for (let i = 1; i <= 8; i++) await page.mouse.move(a.x + ((b.x - a.x) * i) / 8, a.y + ((b.y - a.y) * i) / 8);
    await preview;
    assert((await request(page)).scene.solids[0].center[0] === 2, "the editor keeps the chair until the drop");
    await page.mouse.up();
    await idle(page);
    const after = await request(page);
    const moved = after.scene.solids[0].center;
    assert(near(moved, [3, 2.5], 0.08), `the chair followed the pointer on the floor to (3, 2.5): ${moved}`);
    assert(near(after.camera.position, before.camera.position) && near(after.camera.target, before.camera.target),
      "the camera stayed");
    const last = sent[sent.length - 1];
    assert(last.options.width === full.width && near(last.scene.solids[0].center, moved), `the last render is full size with the moved chair: ${JSON.stringify(last.options)}`);
    await page.keyboard.press("Control+z");
    assert(near((await request(page)).scene.solids[0].center, [2, 2]), "one undo takes the move back");
  },

  // The anti-aliasing control sets options.antialias, and the render sent carries it.
  async designer_antialias({ page, server }) {
    await openApartment(page, server);
    const sent = page.waitForRequest((r) => r.url().endsWith("/v1/render") && JSON.parse(r.postData()).options?.antialias === 8);
    await page.selectOption("#antialias", "8");
    await sent;
    await idle(page);
    assert((await request(page)).options.antialias === 8, "the request says antialias 8");
    await page.selectOption("#antialias", "1");
    await idle(page);
    assert((await request(page)).options.antialias === 1, "and back to 1");
  },

  // Frame all shows the camera the service chooses for "camera": {"frame": "all"} (to the millimetre).
  async designer_frame_all({ page, server }) {
    await openApartment(page, server);
    const req = await request(page);
    await page.click('[data-action="frame"]');
    await idle(page);
    const shown = (await request(page)).camera;
    const { up, fov_y } = req.camera;
    const answer = await pick(server, { ...req, camera: { frame: "all", up, fov_y }, x: 0, y: 0 });
    assert(near(shown.position, answer.camera.position, 0.0006) && near(shown.target, answer.camera.target, 0.0006),
      `the page frames as the service does: ${JSON.stringify(shown)} vs ${JSON.stringify(answer.camera)}`);
    assert(!near(shown.position, req.camera.position, 0.01), "and the camera moved");
  },
};

const body = scenarios[scenario];
if (!binary || !outDir || !body) {
  console.error(`usage: designer_view.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")})`);
  process.exit(2);
}
process.exit(await runScenario(scenario, { binary, outDir }, body));
