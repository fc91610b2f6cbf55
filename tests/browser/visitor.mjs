// The visitor of walk mode in real Chromium against the real server, as a person would: a Sweet Home
// 3D home (3BedroomApartment with its furniture/) imported, the Walk tool chosen (the visitor starts
// in a room, eye at 1.6 m, near plane of a few centimetres, drawn in the plan), the eye height set
// in its field, then the visitor placed in the plan by a press and aimed by dragging, and walked with
// the arrow keys: into a wall (it stops in front of it) and through a door (it passes).
//   node tests/browser/visitor.mjs BUILD/roomrender OUT_DIR visitor_home
// Reads the home from ROOMRENDER_SHARED (default ../shared next to the repository); skipped without it.
import { runScenario, assert, imageSummary, renderSeq } from "./support.mjs";
import { hooks, idle, request, homeZip, designerReady, waitForNewRender, requireHome } from "./designer_support.mjs";
import { pointInPolygon } from "../../clients/web/src/plan_math.js";
import { collides } from "../../clients/web/src/visitor.js";

const [binary, outDir, scenario] = process.argv.slice(2);
const home = "3BedroomApartment";

const eyeOf = (camera) => [camera.position[0], camera.position[2]];
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);

// A wall's frame in the plan: start, unit direction, unit normal (left of it), length.
function frame(wall) {
  const d = [wall.end[0] - wall.start[0], wall.end[1] - wall.start[1]];
  const length = Math.hypot(...d);
  const u = [d[0] / length, d[1] / length];
  return { s: wall.start, u, n: [-u[1], u[0]], length };
}
const at = (f, along, across) => [f.s[0] + f.u[0] * along + f.n[0] * across, f.s[1] + f.u[1] * along + f.n[1] * across];
const signedAcross = (f, p) => (p[0] - f.s[0]) * f.n[0] + (p[1] - f.s[1]) * f.n[1];

// A site to walk from: a point `metres` off the wall at `along`, in a room and clear of every wall
// (eye at eyeY), the straight path to the wall's centreline (`through`: on to as far beyond it,
// into a room) free of other walls.
function site(scene, rooms, wall, along, metres, eyeY, through = false) {
  const f = frame(wall);
  const others = { walls: scene.walls.filter((w) => w !== wall) };
  for (const side of [1, -1]) {
    const from = at(f, along, side * metres);
    const end = through ? -metres : 0;
    if (!rooms.some((r) => pointInPolygon(from, r)) || collides(scene, from, eyeY)) continue;
    if (through && !rooms.some((r) => pointInPolygon(at(f, along, side * end), r))) continue;
    let clear = true;
    for (let k = 0; k <= 40 && clear; k++) clear = !collides(others, at(f, along, side * (metres + ((end - metres) * k) / 40)), eyeY);
    if (clear) return { f, from, side };
  }
  return null;
}

// Puts the visitor at plan point `from` looking toward `toward`: a press there, a drag toward it.
async function placeVisitor(page, from, toward) {
  const eye = eyeOf((await request(page)).camera);
  if (dist(eye, from) < 1) {
    // A press on the visitor would pick it up: put it elsewhere first (a click in the plan).
    const away = [from[0] + (from[0] > eye[0] ? -2 : 2), from[1]];
    const q = await hooks(page, "worldToPlan", ...away);
    await page.mouse.click(q.x, q.y);
    await idle(page);
  }
  const a = await hooks(page, "worldToPlan", ...from);
  const b = await hooks(page, "worldToPlan", ...toward);
  await page.mouse.move(a.x, a.y);
  await page.mouse.down();
  for (let i = 1; i <= 6; i++) await page.mouse.move(a.x + ((b.x - a.x) * i) / 6, a.y + ((b.y - a.y) * i) / 6);
  await page.mouse.up();
  await idle(page);
  const camera = (await request(page)).camera;
  const scale = (await hooks(page, "worldToPlan", 1, 0)).x - (await hooks(page, "worldToPlan", 0, 0)).x;
  assert(dist(eyeOf(camera), from) <= 1.5 / scale + 1e-3, `the visitor stands where it was put: ${eyeOf(camera)} vs ${from}`);
  const look = [camera.target[0] - camera.position[0], camera.target[2] - camera.position[2]];
  const want = [toward[0] - from[0], toward[1] - from[1]];
  const cos = (look[0] * want[0] + look[1] * want[1]) / (Math.hypot(...look) * Math.hypot(...want));
  assert(cos > 0.99, `and looks where it was dragged: ${look} vs ${want}`);
  return camera;
}

async function walk(page, presses) {
  await page.focus('[data-testid="plan"]');
  for (let i = 0; i < presses; i++) await page.keyboard.press("ArrowUp");
  await idle(page);
  return (await request(page)).camera;
}

const scenarios = {
  async visitor_home({ page, server }) {
    await page.goto(`${server.url}/`);
    await designerReady(page);
    const seq = await renderSeq(page);
    await page.setInputFiles("#file", homeZip(home));
    await waitForNewRender(page, seq, { timeout: 120000 });
    const { scene } = await request(page);
    const rooms = (scene.rooms || []).map((r) => r.points);
    assert(rooms.length >= 5 && scene.walls.length >= 10, `the home has rooms and walls: ${rooms.length}, ${scene.walls.length}`);

    // Walk: the visitor starts inside a room (the home's observer camera, or the room under the
    // plan's centre), at eye height, with a near plane of a few centimetres, drawn in the plan.
    await page.click('button[data-tool="walk"]');
    await idle(page);
    let camera = (await request(page)).camera;
    assert(rooms.some((r) => pointInPolygon(eyeOf(camera), r)), `the visitor starts in a room: ${camera.position}`);
    assert(camera.position[1] === 1.6 && camera.near > 0 && camera.near <= 0.1, `eye at 1.6 m, near plane of centimetres: ${JSON.stringify(camera)}`);
    assert(await page.isVisible('[data-testid="visitor"]'), "the plan draws the visitor");
    const inside = await imageSummary(page);
    assert(inside.width === 640 && inside.colours > 50, `the image shows the inside: ${inside.colours} colours`);

    // The eye height field.
    await page.fill("#eye-height", "1.7");
    await page.press("#eye-height", "Enter");
    await page.waitForFunction(() => window.roomrenderDesigner.request().camera.position[1] === 1.7);
    await idle(page);
    camera = (await request(page)).camera;
    assert(rooms.some((r) => pointInPolygon(eyeOf(camera), r)), "the eye rose where the visitor stands");
    const eyeY = 1.7;

    // Into a wall: 1 m in front of a plain stretch of wall, looking at it; 2 m of steps stop before it.
    let plain = null;
    for (const wall of scene.walls) {
      const f = frame(wall);
      if (f.length < 2) continue;
      const along = f.length / 2;
      const openings = (wall.openings || []).filter((o) => along > o.offset - 0.8 && along < o.offset + o.width + 0.8);
      if (openings.length) continue;
      plain = site(scene, rooms, wall, along, 1, eyeY);
      if (plain) {
        plain.wall = wall;
        break;
      }
    }
    assert(plain, "the home has a plain wall with a room in front of it");
    const faceOf = (s) => at(s.f, (s.f.length) / 2, 0);
    let before = await placeVisitor(page, plain.from, faceOf(plain));
    let after = await walk(page, 8);
    const half = (plain.wall.thickness ?? 0.15) / 2;
    const left = plain.side * signedAcross(plain.f, eyeOf(after));
    assert(left >= half + 0.1 && left < 0.6, `the wall stopped the visitor in front of it: ${left.toFixed(3)} m from its centreline`);
    assert(/wall is in the way/i.test(await page.textContent("#visitor-note")), "the status says a wall is in the way");
    assert(after.position[1] === eyeY && dist(eyeOf(after), eyeOf(before)) > 0.3, `it walked up to the wall: ${eyeOf(before)} -> ${eyeOf(after)}`);

    // Through a door: 1 m before a door opening, looking through it; 2 m of steps pass it.
    let door = null;
    for (const wall of scene.walls) {
      for (const o of wall.openings || []) {
        if (o.type !== "door" || o.width < 0.7) continue;
        door = site(scene, rooms, wall, o.offset + o.width / 2, 1, eyeY, true);
        if (door) {
          Object.assign(door, { wall, along: o.offset + o.width / 2 });
          break;
        }
      }
      if (door) break;
    }
    assert(door, "the home has a door between rooms");
    before = await placeVisitor(page, door.from, at(door.f, door.along, 0));
    const atDoor = await imageSummary(page);
    after = await walk(page, 8);
    const beyond = door.side * signedAcross(door.f, eyeOf(after));
    assert(beyond < -0.9, `the visitor walked through the door: ${beyond.toFixed(3)} m past the wall's centreline`);
    assert(rooms.some((r) => pointInPolygon(eyeOf(after), r)), "into the next room");
    const through = await imageSummary(page);
    assert(through.width === 640 && through.hash !== atDoor.hash, "and the image shows the view from there");
  },
};

const prechecks = {
  async visitor_home(server) {
    await requireHome(server, home);
  },
};

const body = scenarios[scenario];
if (!binary || !outDir || !body) {
  console.error(`usage: visitor.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")})`);
  process.exit(2);
}
process.exit(await runScenario(scenario, { binary, outDir, precheck: prechecks[scenario] }, body));
