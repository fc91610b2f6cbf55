// Builds the web page: esbuild bundles src/main.js with the npm packages it imports, and the bundle
// and src/style.css are inlined into src/index.html, written to index.html (the one file the server
// serves at /). The output is committed so `roomrender serve` needs no node; `--check` rebuilds in
// memory and fails when the committed index.html differs (a CTest test runs it).
//   node build.mjs            write index.html
//   node build.mjs --check    exit 1 if index.html is not what the sources build to
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

const outFile = path.join(here, "index.html");
const html = await buildPage();
if (process.argv.includes("--check")) {
  const committed = fs.existsSync(outFile) ? fs.readFileSync(outFile, "utf8") : "";
  if (committed !== html) {
    console.error("clients/web/index.html is not what clients/web/src builds to: run `npm run build` in clients/web and commit it.");
    process.exit(1);
  }
  console.log(`clients/web/index.html is up to date (${html.length} bytes).`);
} else {
  fs.writeFileSync(outFile, html);
  console.log(`wrote clients/web/index.html (${html.length} bytes)`);
}
