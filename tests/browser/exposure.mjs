// The exposure control in real Chromium against the real server, keyboard and mouse only: moving the
// slider up a stop sends options.exposure 2 and the image on screen gets brighter (its mean
// luminance, measured from the pixels shown); Auto sends "auto", disables the slider and shows
// another image; unticking it goes back to the slider's multiplier.
//   node tests/browser/exposure.mjs BUILD/roomrender OUT_DIR SCENARIO
import { runScenario, assert } from "./support.mjs";

const [binary, outDir, scenario] = process.argv.slice(2);

const shownSeq = (page) => page.evaluate(() => Number(document.getElementById("views").dataset.renderSeq || 0));

async function waitForRender(page, after) {
  await page.waitForFunction((s) => Number(document.getElementById("views").dataset.renderSeq || 0) > s &&
    !document.body.hasAttribute("data-busy"), after);
  return shownSeq(page);
}

// The mean Rec. 709 luminance (0..1) of the image shown in #image, and a hash of its pixels.
function shownImage(page) {
  return page.evaluate(() => {
    const img = document.querySelector("#image");
    const canvas = document.createElement("canvas");
    canvas.width = img.naturalWidth;
    canvas.height = img.naturalHeight;
    const ctx = canvas.getContext("2d");
    ctx.drawImage(img, 0, 0);
    const data = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
    let sum = 0;
    let hash = 2166136261;
    for (let i = 0; i < data.length; i += 4) {
      sum += (0.2126 * data[i] + 0.7152 * data[i + 1] + 0.0722 * data[i + 2]) / 255;
      hash = Math.imul(hash ^ ((data[i] << 16) | (data[i + 1] << 8) | data[i + 2]), 16777619) >>> 0;
    }
    return { mean: sum / (data.length / 4), hash };
  });
}

// The request the page holds, as the next render would send it.
const sentOptions = (request) => JSON.parse(request.postData()).options || {};

const scenarios = {
  async exposure_control({ page, server }) {
    await page.goto(`${server.url}/`);
    let seq = await waitForRender(page, 0);
    await page.selectOption("#example", "studio");
    seq = await waitForRender(page, seq);
    const before = await shownImage(page);
    assert(await page.isVisible("text=Exposure"), "the toolbar shows an Exposure control");
    assert((await page.inputValue("#exposure")) === "0", "the slider starts at 0 stops");

    // Two steps right of 0.5 stop each: exposure 2^1.
    const sent = page.waitForRequest((r) => r.url().endsWith("/v1/render") && sentOptions(r).exposure === 2);
    await page.focus("#exposure");
    await page.keyboard.press("ArrowRight");
    await page.keyboard.press("ArrowRight");
    await sent;
    seq = await waitForRender(page, seq);
    const brighter = await shownImage(page);
    assert((await page.textContent("#exposure-value")) === "2×", `the control reads 2×: ${await page.textContent("#exposure-value")}`);
    assert(brighter.mean > before.mean * 1.2, `the image got brighter: mean ${before.mean.toFixed(3)} -> ${brighter.mean.toFixed(3)}`);

    // Auto: the server picks the multiplier; the slider waits.
    const autoSent = page.waitForRequest((r) => r.url().endsWith("/v1/render") && sentOptions(r).exposure === "auto");
    await page.click("#exposure-auto");
    await autoSent;
    seq = await waitForRender(page, seq);
    const auto = await shownImage(page);
    assert(await page.isDisabled("#exposure"), "the slider is disabled under Auto");
    assert(auto.hash !== brighter.hash, "Auto shows another image than 2×");

    // Unticked: back to the slider's 2×, the same image as before.
    const back = page.waitForRequest((r) => r.url().endsWith("/v1/render") && sentOptions(r).exposure === 2);
    await page.click("#exposure-auto");
    await back;
    await waitForRender(page, seq);
    assert(!(await page.isDisabled("#exposure")), "the slider is back");
    assert((await shownImage(page)).hash === brighter.hash, "2× again gives the same image");
  },
};

const body = scenarios[scenario];
if (!binary || !outDir || !body) {
  console.error(`usage: exposure.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")})`);
  process.exit(2);
}
process.exit(await runScenario(scenario, { binary, outDir }, body));
