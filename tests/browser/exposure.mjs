// The exposure control in real Chromium against the real server, keyboard and mouse only: moving the
// slider up a stop sends options.exposure 2 and the image on screen gets brighter (its mean
// luminance, measured from the pixels shown); Auto sends "auto", disables the slider and shows
// another image; unticking it goes back to the slider's multiplier.
// home_exact_shadows: Sweet Home 3D's 3BedroomApartment imported with its furniture/ (from
// ROOMRENDER_SHARED, default ../shared; skipped without it) opens with Phong and exact shadows, shown
// in the toolbar; shadow maps chosen, then exact again, then the exposure moved up a stop: each
// sends its option and changes the image (exact again gives the first image back).
//   node tests/browser/exposure.mjs BUILD/roomrender OUT_DIR SCENARIO
//   node tests/browser/exposure.mjs BUILD/roomrender OUT_DIR --screenshot docs/images/home-exact-shadows.png
//   (home_exact_shadows, then the page as it ends, at 1400 × 900)
import { runScenario, assert, imageSummary, waitForRender, renderSeq } from "./support.mjs";
import { homeZip, designerReady, waitForNewRender, requireHome } from "./designer_support.mjs";

const [binary, outDir, scenarioArg, screenshotPath] = process.argv.slice(2);
const scenario = scenarioArg === "--screenshot" ? "home_exact_shadows" : scenarioArg;

// The request the page holds, as the next render would send it.
const sentOptions = (request) => JSON.parse(request.postData()).options || {};
// A render of the scene inline or of its stored copy.
const isRender = (r) => r.method() === "POST" && /\/render$/.test(new URL(r.url()).pathname);
const home = "3BedroomApartment";

// Does `change` (a person's action) send a render whose options pass `wanted`, and show a new image?
async function changeAndRender(page, change, wanted, what) {
  const seq = await renderSeq(page);
  const sent = page.waitForRequest((r) => isRender(r) && wanted(sentOptions(r)), { timeout: 60000 });
  await change();
  await sent.catch(() => { throw new Error(`${what}: no render sent with the option`); });
  await waitForNewRender(page, seq, { timeout: 120000 });
  return imageSummary(page);
}

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

scenarios.home_exact_shadows = async ({ page }) => {
  const seq = await renderSeq(page);
  await page.setInputFiles("#file", homeZip(home));
  await waitForNewRender(page, seq, { timeout: 120000 });
  // A home opens with Phong and exact shadows, and the toolbar says so.
  const { options } = await page.evaluate(() => window.roomrenderDesigner.request());
  assert(options.shading === "phong" && options.shadows === true && options.shadow?.method === "rays",
    `the home opens with Phong and exact shadows: ${JSON.stringify(options)}`);
  assert((await page.inputValue("#shading")) === "phong", "the toolbar shows Phong");
  assert(await page.isChecked("#shadows"), "the toolbar shows Shadows ticked");
  assert((await page.inputValue("#shadow-method")) === "rays", "the toolbar shows exact shadows");
  const exact = await imageSummary(page);

  const map = await changeAndRender(page, () => page.selectOption("#shadow-method", "map"),
    (o) => o.shadows === true && o.shadow?.method === "map", "shadow maps");
  assert(map.hash !== exact.hash, "shadow maps show another image than exact shadows");
  const again = await changeAndRender(page, () => page.selectOption("#shadow-method", "rays"),
    (o) => o.shadows === true && o.shadow?.method === "rays", "exact shadows");
  assert(again.hash === exact.hash, "exact shadows again give the same image");

  await page.focus("#exposure");
  const brighter = await changeAndRender(page, async () => {
    await page.keyboard.press("ArrowRight");
    await page.keyboard.press("ArrowRight");
  }, (o) => o.exposure === 2 && o.shadow?.method === "rays", "exposure");
  assert(brighter.mean > exact.mean * 1.1, `a stop up brightens the home: mean ${exact.mean.toFixed(3)} -> ${brighter.mean.toFixed(3)}`);
  assert((await page.textContent("#exposure-value")) === "2×", `the control reads 2×: ${await page.textContent("#exposure-value")}`);
};

const prechecks = {
  async home_exact_shadows(server) {
    await requireHome(server, home);
  },
};

const body = scenarios[scenario];
if (!binary || !outDir || !body || (scenarioArg === "--screenshot" && !screenshotPath)) {
  console.error(`usage: exposure.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")}|--screenshot FILE)`);
  process.exit(2);
}
process.exit(await runScenario(scenario, { binary, outDir, precheck: prechecks[scenario] }, async ({ page, server }) => {
  if (scenario === "home_exact_shadows") {
    await page.goto(`${server.url}/`);
    await designerReady(page);
  }
  await body({ page, server });
  if (scenarioArg === "--screenshot") {
    await page.screenshot({ path: screenshotPath });
    console.log(`wrote ${screenshotPath}`);
  }
}));
