// The room designer in real Chromium against the real server, driven with mouse and keyboard only:
// each scenario is one CTest test.
//   node tests/browser/designer.mjs BUILD/roomrender OUT_DIR SCENARIO
//   node tests/browser/designer.mjs BUILD/roomrender OUT_DIR --screenshot docs/images/designer.png
// Plan and image positions come from window.roomrenderDesigner (worldToPlan, viewToPage); the
// request is read back after each step with request(). Waits are on idle() (no render in flight),
// never on fixed sleeps, so a loaded machine only makes them slower.
import { runScenario, assert, imageSummary } from "./support.mjs";
import { hooks, idle, request, near, clickPlan, dragPlan, openEmpty, drawRoom, chooseItem } from "./designer_support.mjs";

const [binary, outDir, scenario, screenshotPath] = process.argv.slice(2);

const scenarios = {
  async designer_room({ page, server }) {
    await openEmpty(page, server);
    const empty = await imageSummary(page);

    await drawRoom(page);

    // A door in the south wall, a window in the east one.
    await page.click('button[data-tool="door"]');
    await clickPlan(page, 2.5, 0);
    let r = await request(page);
    const door = r.scene.walls[0].openings?.[0];
    assert(door && door.type === "door" && Math.abs(door.offset - 2.05) < 1e-6 && door.width === 0.9, `a door at 2.5 m: ${JSON.stringify(door)}`);
    await page.click('button[data-tool="window"]');
    await clickPlan(page, 5, 2);
    r = await request(page);
    const win = r.scene.walls[1].openings?.[0];
    assert(win && win.type === "window" && Math.abs(win.offset - 1.4) < 1e-6, `a window in the east wall: ${JSON.stringify(win)}`);
    // A window over the door is refused in place, with the reason.
    await clickPlan(page, 2.5, 0);
    await page.waitForSelector("#plan-refusal:not([hidden])");
    const reason = await page.textContent("#plan-refusal");
    assert(/overlap/.test(reason), `the refusal says why: ${reason}`);
    assert((await request(page)).scene.walls[0].openings.length === 1, "and nothing was added");

    // A table and a chair from the catalogue.
    await chooseItem(page, "Living room", "table");
    await clickPlan(page, 2.5, 2);
    await chooseItem(page, "Living room", "chair");
    await clickPlan(page, 1.5, 2);
    r = await request(page);
    assert(r.scene.solids.length === 2, `two solids: ${JSON.stringify(r.scene.solids.map((s) => [s.id, s.center]))}`);
    assert(r.scene.solids[0].id === "table-1" && r.scene.solids[0].type === "piece" && near(r.scene.solids[0].center, [2.5, 2]),
      `the table at (2.5, 2): ${r.scene.solids[0].center}`);
    assert(r.scene.solids[1].id === "chair-1" && near(r.scene.solids[1].center, [1.5, 2]), `the chair at (1.5, 2): ${r.scene.solids[1].center}`);

    // Move the chair by dragging it 1 m toward +Z, then rotate it.
    await page.click('button[data-tool="select"]');
    await dragPlan(page, [1.5, 2], [1.5, 3]);
    r = await request(page);
    assert(near(r.scene.solids[1].center, [1.5, 3], 0.051), `the chair moved to (1.5, 3): ${r.scene.solids[1].center}`);
    assert(await hooks(page, "selection") === "/scene/solids/1", "and is selected");
    await page.keyboard.press("Shift+ArrowLeft");
    r = await request(page);
    assert(near(r.scene.solids[1].center, [1, 3], 0.051), `Shift+← moved it 0.5 m: ${r.scene.solids[1].center}`);
    await page.keyboard.press("Shift+ArrowRight");
    await page.keyboard.press("r");
    r = await request(page);
    assert(r.scene.solids[1].rotation_y === 15, `R turned it 15°: ${r.scene.solids[1].rotation_y}`);

    // Delete the table.
    await clickPlan(page, 2.5, 2);
    assert(await hooks(page, "selection") === "/scene/solids/0", "a click selects the table");
    await page.keyboard.press("Delete");
    r = await request(page);
    assert(r.scene.solids.length === 1 && r.scene.solids[0].id === "chair-1", `only the chair is left: ${r.scene.solids.map((s) => s.id)}`);

    // Undo twice (the delete, the rotation), redo once (the rotation).
    await page.keyboard.press("Control+z");
    r = await request(page);
    assert(r.scene.solids.length === 2 && r.scene.solids[0].id === "table-1", "undo brings the table back");
    await page.keyboard.press("Control+z");
    r = await request(page);
    assert((r.scene.solids[1].rotation_y ?? 0) === 0, `a second undo takes the rotation back: ${r.scene.solids[1].rotation_y}`);
    assert(near(r.scene.solids[1].center, [1.5, 3], 0.051), "but not the move");
    await page.keyboard.press("Control+Shift+z");
    r = await request(page);
    assert(r.scene.solids[1].rotation_y === 15 && r.scene.solids.length === 2, "redo turns the chair again, the table stays");

    // The render follows: the room is in the image where the empty scene was plain background.
    await idle(page);
    const shown = await imageSummary(page);
    assert(shown.width === 640 && shown.hash !== empty.hash && shown.colours > empty.colours,
      `the image changed: ${JSON.stringify(empty)} -> ${JSON.stringify(shown)}`);
    // The plan follows the request: four walls, two openings, two solids.
    const drawn = await page.$$eval('[data-testid="plan"] [data-pointer]', (els) => els.map((e) => e.dataset.pointer));
    for (const p of ["/scene/walls/3", "/scene/walls/0/openings/0", "/scene/walls/1/openings/0", "/scene/solids/0", "/scene/solids/1"]) {
      assert(drawn.includes(p), `the plan draws ${p}: ${drawn}`);
    }
  },

  // The properties panel edits the selection within the schema's limits; a text edit in the editor
  // is one undo step of the designer.
  async designer_panel({ page, server }) {
    await openEmpty(page, server);
    await drawRoom(page);
    await page.click('button[data-tool="door"]');
    await clickPlan(page, 2.5, 0);
    assert(await hooks(page, "selection") === "/scene/walls/0/openings/0", "the new door is selected");
    await page.fill('#properties input[data-field="width"]', "1.2");
    await page.press('#properties input[data-field="width"]', "Enter");
    let r = await request(page);
    assert(r.scene.walls[0].openings[0].width === 1.2, `the panel widened the door: ${JSON.stringify(r.scene.walls[0].openings[0])}`);
    await page.fill('#properties input[data-field="width"]', "9");
    await page.press('#properties input[data-field="width"]', "Enter");
    await page.waitForSelector("#plan-refusal:not([hidden])");
    r = await request(page);
    assert(r.scene.walls[0].openings[0].width === 1.2, "a door wider than its wall is refused");
    await idle(page);

    // Replace the text as a paste would: the plan follows, and one Ctrl+Z (outside the editor) takes
    // the whole paste back.
    const edited = structuredClone(r);
    edited.scene.solids.push({ type: "box", id: "pasted", center: [1, 1], size: [0.5, 0.5, 0.5] });
    await page.click(".cm-content");
    await page.keyboard.press("Control+A");
    await page.keyboard.insertText(JSON.stringify(edited, null, 2));
    await page.waitForSelector('[data-testid="plan"] [data-pointer="/scene/solids/0"]');
    await page.click('button[data-tool="select"]');
    const p = await hooks(page, "worldToPlan", 4, 3);
    await page.mouse.click(p.x, p.y);  // the plan takes the keyboard
    await page.keyboard.press("Control+z");
    r = await request(page);
    assert(r.scene.solids.length === 0 && r.scene.walls[0].openings[0].width === 1.2, `undo took the paste back: ${JSON.stringify(r.scene.solids)}`);
    await page.keyboard.press("Control+z");
    r = await request(page);
    assert(r.scene.walls[0].openings[0].width === 0.9, "and then the panel's edit");

    // A point light by a click; Shift+click aims the sun; Ctrl+D duplicates the selected light.
    await page.click('button[data-tool="light"]');
    await clickPlan(page, 2.5, 2);
    r = await request(page);
    const light = r.scene.lights[r.scene.lights.length - 1];
    assert(light.type === "point" && near(light.position, [2.5, 2.4, 2]), `a point light at (2.5, 2): ${JSON.stringify(light)}`);
    const sunBefore = r.scene.lights.find((l) => l.type === "directional").direction;
    await page.keyboard.down("Shift");
    await clickPlan(page, 4, 1);
    await page.keyboard.up("Shift");
    r = await request(page);
    const sun = r.scene.lights.find((l) => l.type === "directional").direction;
    assert(!near(sun, sunBefore) && sun[1] === -1, `Shift+click turned the sun: ${sunBefore} -> ${sun}: ${JSON.stringify(r.scene.lights)}`);
    await page.click('button[data-tool="select"]');
    await clickPlan(page, 2.5, 2);
    assert(/^\/scene\/lights\/\d+$/.test(await hooks(page, "selection")), "a click selects the light");
    const count = r.scene.lights.length;
    await page.keyboard.press("Control+d");
    assert((await request(page)).scene.lights.length === count + 1, "Ctrl+D duplicated it");

    // The panel sets a wall's thickness, and the next walls drawn take it.
    await clickPlan(page, 0, 2);
    assert(await hooks(page, "selection") === "/scene/walls/3", "a click selects the west wall");
    await page.fill('#properties input[data-field="thickness"]', "0.25");
    await page.press('#properties input[data-field="thickness"]', "Enter");
    assert((await request(page)).scene.walls[3].thickness === 0.25, "the panel set its thickness");
    await page.click('button[data-tool="wall"]');
    await clickPlan(page, 1.5, 0);
    await clickPlan(page, 1.5, 4);
    await page.keyboard.press("Escape");
    r = await request(page);
    const inner = r.scene.walls[4];
    assert(inner && near(inner.start, [1.5, 0]) && near(inner.end, [1.5, 4]) && inner.thickness === 0.25,
      `a new wall takes the selected wall's thickness: ${JSON.stringify(inner)}`);

    // Dragging the (selected) new wall moves it; dragging one of its ends moves that end only.
    await page.evaluate(() => window.scrollTo(0, 0));  // typing in the panel scrolled the page
    await page.click('button[data-tool="select"]');
    await dragPlan(page, [1.5, 2], [1, 2]);
    r = await request(page);
    assert(near(r.scene.walls[4].start, [1, 0]) && near(r.scene.walls[4].end, [1, 4]), `the wall moved 0.5 m: ${JSON.stringify(r.scene.walls[4])}`);
    await dragPlan(page, [1, 4], [1, 3]);
    r = await request(page);
    assert(near(r.scene.walls[4].start, [1, 0]) && near(r.scene.walls[4].end, [1, 3]), `its end moved: ${JSON.stringify(r.scene.walls[4])}`);
    assert(near(r.scene.walls[2].end, [0, 4]) && near(r.scene.walls[3].start, [0, 4]), "the room's corners stayed");
    // A corner of the room moves both walls meeting there.
    await clickPlan(page, 0, 2);
    await dragPlan(page, [0, 4], [0, 4.5]);
    r = await request(page);
    assert(near(r.scene.walls[2].end, [0, 4.5]) && near(r.scene.walls[3].start, [0, 4.5]), `the corner moved both walls: ${JSON.stringify(r.scene.walls.slice(2, 4))}`);
  },

  // Placement warnings of the answer are outlined on their elements in the plan, with the message as
  // a tooltip, and listed in a collapsible list filtered by kind.
  async designer_warnings({ page, server }) {
    await openEmpty(page, server);
    await drawRoom(page);
    await chooseItem(page, null, "box");
    await clickPlan(page, 5, 2);     // through the east wall
    await clickPlan(page, 2.5, 2);   // free standing
    await idle(page);
    await page.waitForSelector('[data-testid="plan"] [data-pointer="/scene/solids/0"].mark-warning');
    const tip = await page.textContent('[data-testid="plan"] [data-pointer="/scene/solids/0"] title');
    assert(tip.length > 0, "the outline carries the message");
    assert(!(await page.$('[data-testid="plan"] [data-pointer="/scene/solids/1"].mark-warning')), "the free box is not marked");
    const items = await page.$$eval("#warning-list li.warning", (lis) => lis.map((li) => li.dataset.kind + ": " + li.textContent));
    assert(items.length >= 1 && items.every((t) => t.includes("/scene/solids/0") || t.includes("/scene/walls/1")), `the list names the clash: ${items}`);
    const kinds = await page.$$eval("#warning-kind option", (os) => os.map((o) => o.value).filter(Boolean));
    await page.selectOption("#warning-kind", kinds[0]);
    const filtered = await page.$$eval("#warning-list li.warning", (lis) => lis.map((li) => li.dataset.kind));
    assert(filtered.length >= 1 && filtered.every((k) => k === kinds[0]), `the filter keeps one kind: ${filtered}`);
    await page.click("#warnings-summary");
    assert(!(await page.$eval("#warnings", (d) => d.open)), "the list collapses");
  },

  async designer_walk({ page, server }) {
    await openEmpty(page, server);
    await drawRoom(page);
    await idle(page);
    await page.click('button[data-tool="walk"]');
    await page.waitForFunction(() => window.roomrenderDesigner.request().camera.position[1] === 1.6);
    await idle(page);
    const before = (await request(page)).camera;
    for (let i = 0; i < 8; i++) await page.keyboard.press("ArrowUp");
    const after = (await request(page)).camera;
    const moved = Math.hypot(after.position[0] - before.position[0], after.position[2] - before.position[2]);
    assert(Math.abs(moved - 2) < 0.01 && after.position[1] === 1.6, `8 presses walked 2 m at eye height: ${before.position} -> ${after.position}`);
    const targetMoved = after.target.map((v, i) => v - before.target[i]);
    assert(near(targetMoved, after.position.map((v, i) => v - before.position[i]), 0.002), "the target moved with the eye");
    await page.keyboard.press("Shift+ArrowDown");
    const back = (await request(page)).camera;
    assert(Math.abs(Math.hypot(back.position[0] - after.position[0], back.position[2] - after.position[2]) - 1) < 0.01, "Shift walks 1 m");
    await idle(page);

    // Dragging the image looks around: the eye stays, the target turns; renders come back at half
    // size while the drag goes on, and the image is full size at rest.
    const sizes = [];
    const isRender = (req) => req.url().endsWith("/v1/render");
    page.on("request", (req) => {
      if (isRender(req)) sizes.push(JSON.parse(req.postData()).options?.width);
    });
    // Held until a half-size render was asked for: the page may gather all moves into one frame.
    const preview = page.waitForRequest((req) => isRender(req) && JSON.parse(req.postData()).options?.width === 320);
    const a = await hooks(page, "viewToPage", 320, 240);
    await page.mouse.move(a.x, a.y);
    await page.mouse.down();
    for (let i = 1; i <= 6; i++) await page.mouse.move(a.x + i * 10, a.y);
    await preview;
    await page.mouse.up();
    await idle(page);
    const looked = (await request(page)).camera;
    assert(near(looked.position, back.position) && !near(looked.target, back.target), `look-around turns the target only: ${JSON.stringify(looked)}`);
    const shown = await imageSummary(page);
    assert(shown.width === 640 && shown.height === 480, `the image at rest is full size: ${shown.width}×${shown.height}`);
    assert(sizes.includes(320) && sizes[sizes.length - 1] === 640, `half size while dragging, then full: ${sizes}`);
  },

  // Dragging a chair in the plan renders the dragged scene at half size as it goes; the drop renders
  // the edited request in full.
  async designer_plan_preview({ page, server }) {
    await openEmpty(page, server);
    await chooseItem(page, "Living room", "chair");
    await clickPlan(page, 2, 2);
    await idle(page);
    await page.click('button[data-tool="select"]');
    const sizes = [];
    const isRender = (req) => req.url().endsWith("/v1/render");
    page.on("request", (req) => {
      if (isRender(req)) sizes.push(JSON.parse(req.postData()).options?.width);
    });
    const preview = page.waitForRequest((req) => isRender(req) && JSON.parse(req.postData()).options?.width === 320 &&
      JSON.parse(req.postData()).scene.solids[0].center[0] > 2);
    const a = await hooks(page, "worldToPlan", 2, 2);
    const b = await hooks(page, "worldToPlan", 3, 2);
    await page.mouse.move(a.x, a.y);
    await page.mouse.down();
    for (let i = 1; i <= 5; i++) await page.mouse.move(a.x + ((b.x - a.x) * i) / 5, a.y);
    await preview;
    assert((await request(page)).scene.solids[0].center[0] === 2, "the editor keeps the chair until the drop");
    await page.mouse.up();
    await idle(page);
    const r = await request(page);
    assert(near(r.scene.solids[0].center, [3, 2], 0.051), `the drop moved the chair: ${r.scene.solids[0].center}`);
    assert(sizes.includes(320) && sizes[sizes.length - 1] === 640, `half size while dragging, then full: ${sizes}`);
    const shown = await imageSummary(page);
    assert(shown.width === 640, `the image at rest is full size: ${shown.width}`);
  },

  async designer_autosave({ page, server }) {
    await openEmpty(page, server);
    await chooseItem(page, "Bedroom", "bed140x190");
    await clickPlan(page, 1, 1);
    await page.click('[data-action="save"]');
    await page.reload();
    await page.waitForFunction(() => window.roomrenderDesigner && window.roomrenderDesigner.request());
    await idle(page);
    const r = await request(page);
    assert(r.scene.solids.length === 1 && r.scene.solids[0].id === "bed140x190-1",
      `the bed is restored: ${JSON.stringify(r.scene.solids.map((s) => s.id))}`);
  },
};

// The picture of the designer for the docs (not a test): a furnished room, the chair selected.
async function screenshot({ page, server }) {
  await openEmpty(page, server);
  await drawRoom(page);
  await page.click('button[data-tool="door"]');
  await clickPlan(page, 1.2, 4);
  await page.click('button[data-tool="window"]');
  await clickPlan(page, 5, 2);
  await clickPlan(page, 2.5, 0);
  for (const [category, item, x, z] of [["Bedroom", "bed140x190", 1.1, 1.3], ["Living room", "table", 3.5, 2.6],
    ["Living room", "chair", 3.5, 3.3], ["Living room", "sofa", 3.6, 0.7], ["Lights", "floor_uplight", 4.6, 3.6]]) {
    await chooseItem(page, category, item);
    await clickPlan(page, x, z);
  }
  await page.keyboard.press("r");
  await page.click('button[data-tool="light"]');
  await clickPlan(page, 2.5, 2);
  await page.click('button[data-tool="select"]');
  await clickPlan(page, 3.5, 3.3);
  await page.click('[data-action="frame"]');
  await idle(page);
  await page.screenshot({ path: screenshotPath });
  console.log(`wrote ${screenshotPath}`);
}

const body = scenario === "--screenshot" ? screenshot : scenarios[scenario];
if (!binary || !outDir || !body || (scenario === "--screenshot" && !screenshotPath)) {
  console.error(`usage: designer.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")}|--screenshot FILE)`);
  process.exit(2);
}
process.exit(await runScenario(scenario.replace(/^--/, ""), { binary, outDir }, body));
