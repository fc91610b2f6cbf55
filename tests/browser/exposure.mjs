// The exposure control in real Chromium against the real server, keyboard and mouse only: moving the
// slider up a stop sends options.exposure 2 and the image on screen gets brighter (its mean
// luminance, measured from the pixels shown); Auto sends "auto", disables the slider and shows
// another image; unticking it goes back to the slider's multiplier.
//   node tests/browser/exposure.mjs BUILD/roomrender OUT_DIR SCENARIO
import { runScenario, assert, imageSummary, waitForRender } from "./support.mjs";

const [binary, outDir, scenario] = process.argv.slice(2);

// The request the page holds, as the next render would send it.
const sentOptions = (request) => JSON.parse(request.postData()).options || {};

const scenarios = {
  async exposure_control({ page, server }) {
    await page.goto(`${server.url}/`);
    let seq = await waitForRender(page, 0);
    await page.selectOption("#example", "studio");
    seq = await waitForRender(page, seq);
    const before = await imageSummary(page);
    assert(await page.isVisible("text=Exposure"), "the toolbar shows an Exposure control");
    assert((await page.inputValue("#exposure")) === "0", "the slider starts at 0 stops");

    // Two steps right of 0.5 stop each: exposure 2^1.
    const sent = page.waitForRequest((r) => r.url().endsWith("/v1/render") && sentOptions(r).exposure === 2);
    await page.focus("#exposure");
    await page.keyboard.press("ArrowRight");
    await page.keyboard.press("ArrowRight");
    await sent;
    seq = await waitForRender(page, seq);
    const brighter = await imageSummary(page);
    assert((await page.textContent("#exposure-value")) === "2×", `the control reads 2×: ${await page.textContent("#exposure-value")}`);
    assert(brighter.mean > before.mean * 1.2, `the image got brighter: mean ${before.mean.toFixed(3)} -> ${brighter.mean.toFixed(3)}`);

    // Auto: the server picks the multiplier; the slider waits.
    const autoSent = page.waitForRequest((r) => r.url().endsWith("/v1/render") && sentOptions(r).exposure === "auto");
    await page.click("#exposure-auto");
    await autoSent;
    seq = await waitForRender(page, seq);
    const auto = await imageSummary(page);
    assert(await page.isDisabled("#exposure"), "the slider is disabled under Auto");
    assert(auto.hash !== brighter.hash, "Auto shows another image than 2×");

    // Unticked: back to the slider's 2×, the same image as before.
    const back = page.waitForRequest((r) => r.url().endsWith("/v1/render") && sentOptions(r).exposure === 2);
    await page.click("#exposure-auto");
    await back;
    await waitForRender(page, seq);
    assert(!(await page.isDisabled("#exposure")), "the slider is back");
    assert((await imageSummary(page)).hash === brighter.hash, "2× again gives the same image");
  },
};

const body = scenarios[scenario];
if (!binary || !outDir || !body) {
  console.error(`usage: exposure.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")})`);
  process.exit(2);
}
process.exit(await runScenario(scenario, { binary, outDir }, body));
