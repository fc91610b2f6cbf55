// Builds the web page: esbuild bundles src/main.js with the npm packages it imports, and the bundle
// and src/style.css are inlined into src/index.html, written to index.html (the one file the server
// serves at /). Also copies Redoc's standalone bundle and its licence from node_modules into docs/,
// beside docs/index.html, the API page the server serves at /docs. The outputs are committed so
// `roomrender serve` needs no node; `--check` rebuilds in memory and fails when a committed output
// differs (a CTest test runs it).
//   node build.mjs            write index.html and docs/redoc.standalone.js*
//   node build.mjs --check    exit 1 if they are not what the sources and packages build to
import * as esbuild from "esbuild";
import fs from "node:fs";
import path from "node:path";
import { fileURLToPath } from "node:url";

const here = path.dirname(fileURLToPath(import.meta.url));
const read = (p) => fs.readFileSync(path.join(here, p), "utf8");

// The bundled packages with their licence texts, as the licences ask for copies to carry them.
function notices(metafile) {
  const packages = new Map();
  for (const input of Object.keys(metafile.inputs)) {
    const m = /node_modules\/((?:@[^/]+\/)?[^/]+)\//.exec(input);
    if (!m || packages.has(m[1])) continue;
    const dir = path.join(here, "node_modules", m[1]);
    const meta = JSON.parse(fs.readFileSync(path.join(dir, "package.json"), "utf8"));
    const licenceFile = fs.readdirSync(dir).find((f) => /^licen[cs]e/i.test(f));
    const text = licenceFile ? fs.readFileSync(path.join(dir, licenceFile), "utf8").trim() : `(${meta.license})`;
    packages.set(m[1], `${m[1]} ${meta.version} (${meta.license})\n\n${text}`);
  }
  const list = [...packages.keys()].sort().map((k) => packages.get(k));
  return "Third-party code bundled into this page:\n\n" + list.join("\n\n----\n\n");
}

export async function buildPage() {
  const result = await esbuild.build({
    entryPoints: [path.join(here, "src/main.js")],
    bundle: true,
    minify: true,
    format: "iife",
    target: ["chrome100", "firefox100", "safari15"],
    charset: "utf8",
    legalComments: "none",  // the notices below carry the licences whole
    metafile: true,
    write: false,
    logLevel: "warning",
  });
  // "</script" would end the inline script early; "<\/" means the same inside JS strings and regexes.
  const script = result.outputFiles[0].text.replace(/<\/(script)/gi, "<\\/$1");
  if (/<!--/.test(script)) throw new Error("the bundle contains '<!--', which an inline script must not");
  const text = notices(result.metafile).replace(/--/g, "- -");
  return read("src/index.html")
    .replace("/*STYLE*/", () => read("src/style.css").trim())
    .replace("/*SCRIPT*/", () => script.trim())
    .replace("</body>", () => `<!--\n${text}\n-->\n</body>`);
}

// Redoc's one fetch from elsewhere: the logo beside "API docs by Redocly", from its CDN. Emptied, the
// image fails at once and Redoc drops it (its onError), so the page asks no other host for anything.
const redocLogo = "https://cdn.redoc.ly/redoc/logo-mini.svg";
function withoutCdn(text) {
  const uses = text.split(redocLogo).length - 1;
  if (uses !== 1) throw new Error(`redoc.standalone.js names ${redocLogo} ${uses} times, not once: look at it again`);
  return text.replace(redocLogo, "");
}

// The API page loads Redoc as a file of its own: a megabyte of script that a browser caches, and that
// an inline <script> could not hold (it contains "<!--").
const vendored = [
  { out: "docs/redoc.standalone.js", text: withoutCdn(read("node_modules/redoc/bundles/redoc.standalone.js")) },
  { out: "docs/redoc.standalone.js.LICENSE.txt", text: read("node_modules/redoc/bundles/redoc.standalone.js.LICENSE.txt") },
];
const outputs = [{ out: "index.html", text: await buildPage() }, ...vendored];

if (process.argv.includes("--check")) {
  let stale = 0;
  for (const { out, text } of outputs) {
    const file = path.join(here, out);
    const committed = fs.existsSync(file) ? fs.readFileSync(file, "utf8") : "";
    if (committed === text) continue;
    console.error(`clients/web/${out} is not what clients/web builds to: run \`npm run build\` in clients/web and commit it.`);
    stale += 1;
  }
  if (stale) process.exit(1);
  console.log(`clients/web outputs are up to date (${outputs.map((o) => `${o.out} ${o.text.length} bytes`).join(", ")}).`);
} else {
  for (const { out, text } of outputs) {
    fs.writeFileSync(path.join(here, out), text);
    console.log(`wrote clients/web/${out} (${text.length} bytes)`);
  }
}
