// The texture palette in real Chromium against the real server, as a person would: four walls drawn,
// a catalogue texture picked in the palette, a click on one side of a wall puts it there (the plan
// fills that half of the wall; in the image only the pixels of that face change), Ctrl+Z gives back
// the image before to the byte, Ctrl+Shift+Z the textured one; Save's permalink opened in a new page
// carries the texture by its stored image's id and draws the same bytes; an uploaded PNG joins the
// palette and goes onto another side.
//   node tests/browser/textures.mjs BUILD/roomrender OUT_DIR designer_texture_palette
import path from "node:path";
import { runScenario, assert, skip, repoRoot, serverHas, renderSeq } from "./support.mjs";
import { hooks, idle, request, openEmpty, drawRoom, clickPlan, designerReady, waitForNewRender, worldToImage } from "./designer_support.mjs";

const [binary, outDir, scenario] = process.argv.slice(2);

// The RGB pixels of a base64 PNG, decoded by the page: {width, height, data}.
function pixels(page, png) {
  return page.evaluate(async (b64) => {
    const img = new Image();
    img.src = `data:image/png;base64,${b64}`;
    await img.decode();
    const canvas = document.createElement("canvas");
    canvas.width = img.naturalWidth;
    canvas.height = img.naturalHeight;
    const ctx = canvas.getContext("2d");
    ctx.drawImage(img, 0, 0);
    return { width: canvas.width, height: canvas.height, data: [...ctx.getImageData(0, 0, canvas.width, canvas.height).data] };
  }, png);
}

// Where two images differ: the bounding box of the pixels that changed, and how many did.
function difference(a, b) {
  let count = 0;
  const box = [Infinity, Infinity, -Infinity, -Infinity];
  for (let i = 0; i < a.data.length; i += 4) {
    if (a.data[i] === b.data[i] && a.data[i + 1] === b.data[i + 1] && a.data[i + 2] === b.data[i + 2]) continue;
    const x = (i / 4) % a.width;
    const y = Math.floor(i / 4 / a.width);
    count++;
    box[0] = Math.min(box[0], x);
    box[1] = Math.min(box[1], y);
    box[2] = Math.max(box[2], x);
    box[3] = Math.max(box[3], y);
  }
  return { count, box };
}

const scenarios = {
  async designer_texture_palette({ page, server, context }) {
    if (!(await serverHas(server, "/v1/catalogue/textures", "get"))) skip("needs GET /v1/catalogue/textures");
    await openEmpty(page, server);
    await drawRoom(page);
    await idle(page);
    const plain = await hooks(page, "png");
    const r0 = await request(page);
    const wall = r0.scene.walls[2];  // [5, 4] -> [0, 4]: its left side faces +z, toward the camera
    assert(wall.start[1] === 4 && wall.end[1] === 4, `the near wall runs along z = 4: ${JSON.stringify(wall)}`);

    // Pick "Red tiles" in the palette (the Texture tool is taken up) and click the near wall's outer half.
    await page.click('#texture-items button[aria-label="Red tiles"]');
    assert(await page.getAttribute('button[data-tool="texture"]', "aria-pressed") === "true", "picking a texture chooses the Texture tool");
    let seq = await renderSeq(page);
    await clickPlan(page, 2.5, 4 + wall.thickness / 4);
    await waitForNewRender(page, seq);
    const r1 = await request(page);
    const texture = r1.scene.walls[2].left_texture;
    assert(texture && /^[0-9a-f]{16}$/.test(texture.image) && texture.width === 0.4 && texture.height === 0.4,
      `the wall's left side takes the catalogue image by id at its 40 cm tile: ${JSON.stringify(r1.scene.walls[2])}`);
    assert(!r1.scene.walls[2].right_texture && r1.scene.walls.every((w, i) => i === 2 || (!w.left_texture && !w.right_texture)),
      "and no other side");
    const strip = await page.$$eval('#plan polygon.wall-side-texture', (els) => els.map((e) => ({ side: e.dataset.side, fill: e.getAttribute("fill") })));
    assert(strip.length === 1 && strip[0].side === "left" && /^url\(#texture-/.test(strip[0].fill), `the plan fills that half of the wall: ${JSON.stringify(strip)}`);

    // In the image, only pixels of the wall's outer face changed, and most of its middle did.
    const textured = await hooks(page, "png");
    const [a, b] = [await pixels(page, plain), await pixels(page, textured)];
    const diff = difference(a, b);
    // The outer face runs past the room's corners by half a wall's thickness, to the side walls' outer faces.
    const h = wall.thickness / 2;
    const corners = [[-h, 0], [5 + h, 0], [-h, wall.height], [5 + h, wall.height]].map(([x, y]) => worldToImage(r1.camera, r1.options, [x, y, 4 + h]));
    const face = [Math.min(...corners.map((c) => c[0])), Math.min(...corners.map((c) => c[1])), Math.max(...corners.map((c) => c[0])), Math.max(...corners.map((c) => c[1]))];
    const margin = 2;
    assert(diff.count > 0 && diff.box[0] >= face[0] - margin && diff.box[1] >= face[1] - margin && diff.box[2] <= face[2] + margin && diff.box[3] <= face[3] + margin,
      `the ${diff.count} changed pixels (box ${diff.box}) lie on the wall's face (${face.map(Math.round)})`);
    const inner = [face[0] + 0.3 * (face[2] - face[0]), face[1] + 0.3 * (face[3] - face[1]), face[0] + 0.7 * (face[2] - face[0]), face[1] + 0.7 * (face[3] - face[1])].map(Math.round);
    let changed = 0;
    let total = 0;
    for (let y = inner[1]; y <= inner[3]; y++) {
      for (let x = inner[0]; x <= inner[2]; x++) {
        const i = (y * a.width + x) * 4;
        total++;
        if (Math.abs(a.data[i] - b.data[i]) + Math.abs(a.data[i + 1] - b.data[i + 1]) + Math.abs(a.data[i + 2] - b.data[i + 2]) > 6) changed++;
      }
    }
    assert(total > 100 && changed / total > 0.8, `most of the face's middle changed: ${changed} of ${total} pixels`);

    // Ctrl+Z: the image before, to the byte; Ctrl+Shift+Z: the textured one again.
    seq = await renderSeq(page);
    await page.keyboard.press("Control+z");
    await waitForNewRender(page, seq);
    assert(!(await request(page)).scene.walls[2].left_texture, "undo takes the texture off");
    assert(await hooks(page, "png") === plain, "and the image is the one before, byte for byte");
    assert(await page.$$eval('#plan polygon.wall-side-texture', (els) => els.length) === 0, "the plan shows no textured side");
    seq = await renderSeq(page);
    await page.keyboard.press("Control+Shift+z");
    await waitForNewRender(page, seq);
    assert(await hooks(page, "png") === textured, "redo puts it back");

    // An uploaded PNG joins the palette, chosen, and goes onto the far wall's inner side.
    seq = await renderSeq(page);
    await page.setInputFiles("#texture-upload", path.join(repoRoot, "catalogue/icons/chair.png"));
    await page.waitForSelector('#texture-items button[aria-label="chair.png"][aria-pressed="true"]');
    await clickPlan(page, 2.5, wall.thickness / 4);
    await waitForNewRender(page, seq);
    const r2 = await request(page);
    const uploaded = r2.scene.walls[0].right_texture;
    assert(uploaded && /^[0-9a-f]{16}$/.test(uploaded.image) && uploaded.image !== texture.image && uploaded.width === 1,
      `the far wall's inner side takes the uploaded image by id: ${JSON.stringify(r2.scene.walls[0])}`);

    // Save: the permalink opened anew carries both textures by id and draws the same bytes.
    await page.click('[data-action="save"]');
    await page.waitForSelector("#share-links:not([hidden])");
    const link = await page.getAttribute("#permalink", "href");
    const shown = await hooks(page, "png");
    const other = await context.newPage();
    await other.goto(link);
    await designerReady(other);
    const r3 = await request(other);
    // A stored scene comes back canonical (keys sorted): compared with sorted keys.
    const same = (x, y) => JSON.stringify(x, Object.keys(x || {}).sort()) === JSON.stringify(y, Object.keys(y || {}).sort());
    assert(same(r3.scene.walls[2].left_texture, texture) && same(r3.scene.walls[0].right_texture, uploaded), `the permalink carries the textures: ${JSON.stringify(r3.scene.walls)}`);
    assert(!JSON.stringify(r3).includes("data:"), "by id, never a data: URI");
    assert(await hooks(other, "png") === shown, "and draws the same PNG bytes");
    await page.screenshot({ path: path.join(outDir, "designer_texture_palette.png") });
    await other.close();
  },
};

const body = scenarios[scenario];
if (!binary || !outDir || !body) {
  console.error(`usage: textures.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")})`);
  process.exit(2);
}
process.exit(await runScenario(scenario, { binary, outDir }, body));
