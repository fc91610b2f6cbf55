// The Room tool in real Chromium against the real server, as a person would: four walls drawn with
// the wall tool, a double-click inside them fills the room to their inner faces (the server draws its
// floor, and its ceiling too from a camera inside; the image changes), its name and area are written
// in the plan; undone, then a room drawn by clicking its corners and the first one again; a
// double-click outside any walls is refused with the reason.
//   node tests/browser/rooms.mjs BUILD/roomrender OUT_DIR designer_room_tool
import { runScenario, assert, httpRequest, imageSummary, renderSeq } from "./support.mjs";
import { request, openEmpty, drawRoom, clickPlan, waitForNewRender, idle, hooks } from "./designer_support.mjs";

const [binary, outDir, scenario] = process.argv.slice(2);

// The polygons the server draws for the page's request.
async function polygons(server, r) {
  const answer = await httpRequest(`${server.url}/v1/render`, {
    method: "POST", headers: { "Content-Type": "application/json", Accept: "application/json" }, body: JSON.stringify(r),
  });
  return JSON.parse(answer.body.toString("utf8")).counts.polygons;
}

const sameRing = (a, b) => a.length === b.length && a.some((_, k) => a.every((p, i) => Math.abs(p[0] - b[(i + k) % b.length][0]) < 1e-9 && Math.abs(p[1] - b[(i + k) % b.length][1]) < 1e-9));

const scenarios = {
  async designer_room_tool({ page, server }) {
    await openEmpty(page, server);
    await drawRoom(page);
    await idle(page);
    const walled = await request(page);
    const thickness = walled.scene.walls[0].thickness;
    const before = { image: await imageSummary(page), polygons: await polygons(server, walled) };

    // Double-click inside the walls: the room reaches their inner faces.
    await page.click('button[data-tool="room"]');
    let seq = await renderSeq(page);
    const mid = await hooks(page, "worldToPlan", 2.5, 2);
    await page.mouse.dblclick(mid.x, mid.y);
    await waitForNewRender(page, seq);
    let r = await request(page);
    const h = thickness / 2;
    assert(r.scene.rooms?.length === 1 && sameRing(r.scene.rooms[0].points, [[h, h], [5 - h, h], [5 - h, 4 - h], [h, 4 - h]]),
      `one room to the walls' inner faces: ${JSON.stringify(r.scene.rooms)}`);
    const area = ((5 - thickness) * (4 - thickness)).toFixed(2);
    const label = await page.textContent('[data-testid="plan"] .room-label');
    assert(label.includes(r.scene.rooms[0].id) && label.includes(`${area} m²`), `the plan names it with its area ${area} m²: ${label}`);
    // From above the server leaves ceilings out (options.ceilings); from inside it draws both.
    const added = (await polygons(server, r)) - before.polygons;
    assert(added === 1, `from the page's aerial camera the server draws its floor: ${added} polygons more`);
    const inside = { position: [2.5, 1.6, 3], target: [2.5, 1.7, 0], fov_y: 60 };
    const addedInside = (await polygons(server, { ...r, camera: inside })) - (await polygons(server, { ...walled, camera: inside }));
    assert(addedInside === 2, `from inside, its floor and its ceiling: ${addedInside} polygons more`);
    assert((await imageSummary(page)).hash !== before.image.hash, "the image shows the floor");

    // Undo, then a room by its corners: four clicks and the first again.
    await page.keyboard.press("Control+z");
    assert(((await request(page)).scene.rooms || []).length === 0, "one undo takes the room away");
    await idle(page);
    seq = await renderSeq(page);
    for (const q of [[1, 1], [3, 1], [3, 3], [1, 3]]) await clickPlan(page, ...q);
    assert(((await request(page)).scene.rooms || []).length === 0, "no room before it is closed");
    await clickPlan(page, 1, 1);
    await waitForNewRender(page, seq);
    r = await request(page);
    assert(r.scene.rooms?.length === 1 && sameRing(r.scene.rooms[0].points, [[1, 1], [3, 1], [3, 3], [1, 3]]),
      `a room on the clicked corners: ${JSON.stringify(r.scene.rooms)}`);
    assert((await page.textContent('[data-testid="plan"] .room-label')).includes("4.00 m²"), "of 4 m²");

    // Outside any walls a double-click refuses, saying what to do.
    await page.mouse.dblclick(...Object.values(await hooks(page, "worldToPlan", -0.5, 2)));
    await page.waitForSelector("#plan-refusal:not([hidden])");
    assert(/closed walls/.test(await page.textContent("#plan-refusal")), "the refusal says why");
  },
};

const body = scenarios[scenario];
if (!binary || !outDir || !body) {
  console.error(`usage: rooms.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")})`);
  process.exit(2);
}
process.exit(await runScenario(scenario, { binary, outDir }, body));
