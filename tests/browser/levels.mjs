// The level tabs in real Chromium against the real server, as a person would: Sweet Home 3D's
// 3BedroomHouseWithAttic (four levels, two viewable) imported with its furniture/, a storey chosen
// by its tab (the image draws it and the storeys below, the plan only its walls), a block dropped
// on the upper storey (it goes on that level, standing on its floor), undo back through the block
// and the tab, then All (every viewable storey, every wall in the plan).
//   node tests/browser/levels.mjs BUILD/roomrender OUT_DIR designer_levels
// Reads the home from ROOMRENDER_SHARED (default ../shared next to the repository); skipped without it.
import { runScenario, assert, imageSummary, renderSeq } from "./support.mjs";
import { request, homeZip, designerReady, waitForNewRender, chooseItem, clickPlan, requireHome } from "./designer_support.mjs";

const [binary, outDir, scenario] = process.argv.slice(2);
const home = "3BedroomHouseWithAttic";

const tabs = (page) => page.$$eval("#levels [role=tab]", (bs) => bs.map((b) => ({ level: b.dataset.level, selected: b.getAttribute("aria-selected") === "true" })));
const chosenTab = async (page) => (await tabs(page)).find((t) => t.selected)?.level;
const planWalls = (page) => page.$$eval('[data-testid="plan"] polygon.wall', (ws) => ws.length);
const drawnLevels = async (page) => JSON.stringify((await request(page)).options.levels);

async function chooseTab(page, level) {
  const seq = await renderSeq(page);
  await page.click(`#levels [role=tab][data-level="${level}"]`);
  await waitForNewRender(page, seq);
}

const scenarios = {
  async designer_levels({ page }) {
    const seq = await renderSeq(page);
    await page.setInputFiles("#file", homeZip(home));
    await waitForNewRender(page, seq, { timeout: 120000 });
    const imported = await request(page);
    const walls = imported.scene.walls.length;
    const onLevel = (id) => imported.scene.walls.filter((w) => w.level === id).length;
    assert(JSON.stringify((await tabs(page)).map((t) => t.level)) === JSON.stringify(["", "level0", "level1", "level2", "level3"]),
      `a tab per level and All: ${JSON.stringify(await tabs(page))}`);
    assert(await chosenTab(page) === "", "All is chosen after the import");
    assert(await planWalls(page) === walls, `the plan shows all ${walls} walls: ${await planWalls(page)}`);
    const all = await imageSummary(page);

    await chooseTab(page, "level0");
    assert(await drawnLevels(page) === '["level0"]', `the ground floor alone is drawn: ${await drawnLevels(page)}`);
    assert(await planWalls(page) === onLevel("level0"), `the plan shows its ${onLevel("level0")} walls: ${await planWalls(page)}`);
    assert((await imageSummary(page)).hash !== all.hash, "the image changed");

    await chooseTab(page, "level1");
    assert(await drawnLevels(page) === '["level0","level1"]', `the first floor and the one below: ${await drawnLevels(page)}`);
    assert(await planWalls(page) === onLevel("level1"), `the plan shows its ${onLevel("level1")} walls: ${await planWalls(page)}`);

    // A block dropped in the middle of the first floor's walls goes on that level, on its floor.
    const upper = imported.scene.walls.filter((w) => w.level === "level1").flatMap((w) => [w.start, w.end]);
    const mid = [0, 1].map((k) => (Math.min(...upper.map((q) => q[k])) + Math.max(...upper.map((q) => q[k]))) / 2);
    let before = await renderSeq(page);
    await chooseItem(page, null, "box");
    await clickPlan(page, ...mid);
    await waitForNewRender(page, before);
    const solids = (await request(page)).scene.solids;
    const block = solids[solids.length - 1];
    assert(solids.length === imported.scene.solids.length + 1 && block.type === "box" && block.level === "level1" && block.base === 2.62,
      `the block is on level1 at 2.62 m: ${JSON.stringify(block)}`);

    // Undo takes the block away, then the tab back to the ground floor.
    await page.keyboard.press("Control+z");
    assert((await request(page)).scene.solids.length === imported.scene.solids.length, "one undo takes the block away");
    await page.keyboard.press("Control+z");
    await page.waitForFunction(() => document.querySelector('#levels [aria-selected="true"]')?.dataset.level === "level0");
    assert(await drawnLevels(page) === '["level0"]' && await planWalls(page) === onLevel("level0"),
      `a second undo goes back to the ground floor's tab: ${await drawnLevels(page)}`);

    before = await renderSeq(page);
    await page.click('#levels [role=tab][data-level=""]');
    await waitForNewRender(page, before);
    assert(await chosenTab(page) === "" && await drawnLevels(page) === '["level0","level1"]', `All draws the viewable levels: ${await drawnLevels(page)}`);
    assert(await planWalls(page) === walls, `and the plan every wall: ${await planWalls(page)}`);
  },
};

const prechecks = {
  async designer_levels(server) {
    await requireHome(server, home);
  },
};

const body = scenarios[scenario];
if (!binary || !outDir || !body) {
  console.error(`usage: levels.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")})`);
  process.exit(2);
}
process.exit(await runScenario(scenario, {
  binary, outDir, precheck: prechecks[scenario],
}, async ({ page, server }) => {
  await page.goto(`${server.url}/`);
  await designerReady(page);
  await body({ page, server });
}));
