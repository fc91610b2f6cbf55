// Support for the browser tests: the real roomrender server on a free loopback port (it prints a
// JSON "listening" line with the port it got), Debian's Chromium driven by playwright-core (from
// clients/web's node_modules), screenshots on failure, and the skip convention CTest understands
// (exit code 77 with a line naming what is missing).
import { spawn } from "node:child_process";
import http from "node:http";
import { createRequire } from "node:module";
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import readline from "node:readline";
import { fileURLToPath } from "node:url";

export const repoRoot = path.resolve(path.dirname(fileURLToPath(import.meta.url)), "../..");
export const skipExitCode = 77;

export class Skip extends Error {}

// Skips the test, naming the endpoint it waits for.
export function skip(reason) {
  // CI has ../shared and a server with every endpoint (.ci/run sets this): there a skip is a failure.
  if (process.env.ROOMRENDER_REQUIRE_SHARED) throw new Error(`would skip, which CI does not allow: ${reason}`);
  throw new Skip(reason);
}

function loadPlaywright() {
  const require = createRequire(path.join(repoRoot, "clients/web/package.json"));
  try {
    return require("playwright-core");
  } catch {
    throw new Error("playwright-core is missing: run `npm ci` in clients/web (scripts/install-deps.sh does)");
  }
}

export function chromiumPath() {
  const candidates = [process.env.ROOMRENDER_CHROMIUM, "/usr/bin/chromium", "/usr/bin/chromium-browser"].filter(Boolean);
  const found = candidates.find((p) => fs.existsSync(p));
  if (!found) throw new Error("Chromium is missing: apt-get install chromium (scripts/install-deps.sh does)");
  return found;
}

// Starts `roomrender serve --port 0` and resolves once it listens: {url, port, stop()}.
export function startServer(binary, extraArgs = []) {
  // extraArgs may name another --web-dir (a flag is given once).
  const web = extraArgs.includes("--web-dir") ? [] : ["--web-dir", path.join(repoRoot, "clients/web")];
  const args = ["serve", "--port", "0", "--bind", "127.0.0.1", "--log-requests", "0",
    ...web, "--examples-dir", path.join(repoRoot, "examples"), ...extraArgs];
  const child = spawn(binary, args, { stdio: ["ignore", "pipe", "pipe"] });
  let stderr = "";
  child.stderr.on("data", (d) => { stderr += d; });
  return new Promise((resolve, reject) => {
    const timer = setTimeout(() => reject(new Error(`server did not report listening in 20 s: ${stderr}`)), 20000);
    child.on("exit", (code) => reject(new Error(`server exited with ${code} before listening: ${stderr}`)));
    readline.createInterface({ input: child.stdout }).on("line", (line) => {
      let event;
      try {
        event = JSON.parse(line);
      } catch {
        return;
      }
      if (event.event !== "listening") return;
      clearTimeout(timer);
      const url = `http://127.0.0.1:${event.port}`;
      resolve({
        url,
        port: event.port,
        stop: () => new Promise((done) => {
          if (child.exitCode !== null) return done();
          child.once("exit", () => done());
          child.kill("SIGTERM");
          setTimeout(() => child.kill("SIGKILL"), 5000).unref();
        }),
      });
    });
  });
}

// One HTTP exchange on its own connection (no keep-alive: an idle connection would hold a server
// thread, and stopping the server would wait for it): {status, headers, body}.
export function httpRequest(url, { method = "GET", headers = {}, body } = {}) {
  return new Promise((resolve, reject) => {
    const req = http.request(url, { method, headers, agent: false }, (res) => {
      const chunks = [];
      res.on("data", (c) => chunks.push(c));
      res.on("end", () => resolve({ status: res.statusCode, headers: res.headers, body: Buffer.concat(chunks) }));
    });
    req.on("error", reject);
    req.end(body);
  });
}

// Does the server have this endpoint? From its OpenAPI document; a server without one (the first
// server) has none of the newer endpoints.
export async function serverHas(server, apiPath, method = "post") {
  const res = await httpRequest(`${server.url}/openapi.json`);
  if (res.status !== 200) return false;
  const paths = JSON.parse(res.body.toString("utf8")).paths || {};
  return Boolean(paths[apiPath] && paths[apiPath][method]);
}

// Runs `body({page, server, browser})` with a fresh server and browser (after `precheck(server)`,
// which may skip); on failure saves a screenshot and the page's console to outDir, and returns the
// process exit code.
export async function runScenario(name, { binary, outDir, precheck, serverArgs = [] }, body) {
  const started = Date.now();
  const { chromium } = loadPlaywright();
  let server = null;
  let browser = null;
  let page = null;
  const consoleLines = [];
  try {
    server = await startServer(binary, serverArgs);
    if (precheck) await precheck(server);
    browser = await chromium.launch({ executablePath: chromiumPath(), args: ["--no-sandbox"] });
    const context = await browser.newContext({ viewport: { width: 1400, height: 900 }, acceptDownloads: true });
    page = await context.newPage();
    // Generous: under a loaded 2-core CI machine a render plus page work took ~11 s (json_answers).
    page.setDefaultTimeout(40000);
    page.on("console", (m) => consoleLines.push(`${m.type()}: ${m.text()}`));
    page.on("pageerror", (e) => consoleLines.push(`pageerror: ${e.message}`));
    await body({ page, server, browser, context });
    console.log(`PASS: browser.${name} (${Date.now() - started} ms)`);
    return 0;
  } catch (error) {
    if (error instanceof Skip) {
      console.log(`SKIP: browser.${name}: ${error.message}`);
      return skipExitCode;
    }
    console.error(`FAIL: browser.${name}: ${error.stack || error}`);
    if (page) {
      fs.mkdirSync(outDir, { recursive: true });
      const shot = path.join(outDir, `${name}.png`);
      await page.screenshot({ path: shot, fullPage: true }).catch(() => {});
      fs.writeFileSync(path.join(outDir, `${name}.console.txt`), consoleLines.join("\n") + "\n");
      console.error(`screenshot: ${shot}`);
    }
    if (consoleLines.length) console.error(`page console:\n  ${consoleLines.join("\n  ")}`);
    return 1;
  } finally {
    if (browser) await browser.close().catch(() => {});
    if (server) await server.stop();
  }
}

export function assert(condition, message) {
  if (!condition) throw new Error(`assertion failed: ${message}`);
}

// The page's count of renders shown so far (#views' data-render-seq).
export const renderSeq = (page) => page.evaluate(() => Number(document.getElementById("views").dataset.renderSeq || 0));

// Waits until a render newer than `after` is on screen and nothing is in flight; its number.
export async function waitForRender(page, after) {
  await page.waitForFunction((s) => Number(document.getElementById("views").dataset.renderSeq || 0) > s &&
    !document.body.hasAttribute("data-busy"), after);
  return renderSeq(page);
}

// An image on the page (the 3D view unless `selector` names another), summarised: its size, the
// number of distinct colours, a hash of its pixels and their mean Rec. 709 luminance (0..1).
export function imageSummary(page, selector = '[data-testid="view"]') {
  return page.evaluate((sel) => {
    const img = document.querySelector(sel);
    const canvas = document.createElement("canvas");
    canvas.width = img.naturalWidth;
    canvas.height = img.naturalHeight;
    const ctx = canvas.getContext("2d");
    ctx.drawImage(img, 0, 0);
    const data = ctx.getImageData(0, 0, canvas.width, canvas.height).data;
    const colours = new Set();
    let hash = 2166136261;
    let luminance = 0;
    for (let i = 0; i < data.length; i += 4) {
      const c = (data[i] << 16) | (data[i + 1] << 8) | data[i + 2];
      colours.add(c);
      hash = Math.imul(hash ^ c, 16777619) >>> 0;
      luminance += (0.2126 * data[i] + 0.7152 * data[i + 1] + 0.0722 * data[i + 2]) / 255;
    }
    const pixels = data.length / 4;
    return { width: canvas.width, height: canvas.height, colours: colours.size, hash, mean: luminance / pixels };
  }, selector);
}

// A token file for `--api-token-file` holding `name:token` lines (tokens: {name: token}); its path.
export function tokenFile(tokens) {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), "rr-tokens-"));
  const file = path.join(dir, "tokens");
  fs.writeFileSync(file, Object.entries(tokens).map(([name, token]) => `${name}:${token}\n`).join(""), { mode: 0o600 });
  return file;
}

// How many times "Your scenes" has loaded its list (each load, shown or refused, adds one).
const listLoads = (page) => page.evaluate(() => Number(document.getElementById("your-scenes").dataset.loads || 0));

// Runs `act` (a click, a key) and waits for the list of "Your scenes" to load again after it.
export async function afterListLoad(page, act) {
  const before = await listLoads(page);
  await act();
  await page.waitForFunction((n) => Number(document.getElementById("your-scenes").dataset.loads || 0) > n, before);
}

// Opens "Your scenes" with a click on its heading and waits for its list.
export async function openYourScenes(page) {
  await afterListLoad(page, () => page.getByText("Your scenes", { exact: true }).click());
}

// The ids "Your scenes" lists, in its order (newest first).
export function listedScenes(page) {
  return page.$$eval("#scenes-list li", (rows) => rows.map((li) => li.dataset.id));
}
