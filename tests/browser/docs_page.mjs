// The API page at /docs in real Chromium against the real server: Redoc draws every operation of
// the OpenAPI document with the request schemas resolved from the served schema files, and the page
// fetches nothing from another origin (nor does the policy have to refuse anything: a refusal
// would mean the page tried). One CTest test.
//   node docs_page.mjs ROOMRENDER OUT_DIR docs_page
import fs from "node:fs";
import path from "node:path";
import { runScenario, assert, repoRoot } from "./support.mjs";

const [binary, outDir, scenario] = process.argv.slice(2);

// A schema file of schemas/, or the part of one a "file#/json/pointer" reference names.
function load(ref) {
  const [file, pointer = ""] = ref.split("#");
  let node = JSON.parse(fs.readFileSync(path.join(repoRoot, "schemas", file), "utf8"));
  for (const key of pointer.split("/").slice(1)) node = node[key];
  return node;
}

const scenarios = {
  async docs_page({ page, server }) {
    const requests = [];
    page.on("request", (r) => requests.push(r.url()));
    const refused = [];
    page.on("console", (m) => { if (/Content Security Policy/i.test(m.text())) refused.push(m.text()); });
    await page.goto(`${server.url}/docs`);

    const openapi = JSON.parse(fs.readFileSync(path.join(repoRoot, "schemas/openapi.json"), "utf8"));
    const summaries = Object.values(openapi.paths).flatMap((item) => Object.values(item).map((op) => op.summary)).filter(Boolean);
    await page.waitForSelector("h2", { timeout: 40000 });
    const text = await page.innerText("body");
    for (const summary of summaries) assert(text.includes(summary), `the page shows the operation "${summary}"`);
    // Each request body's schema is another file: its properties' descriptions are on the page only
    // when Redoc followed the relative $ref to the served file.
    const bodyRefs = new Set(Object.values(openapi.paths).flatMap((item) => Object.values(item))
      .flatMap((op) => Object.values(op.requestBody?.content || {})).map((media) => media.schema?.$ref).filter(Boolean));
    assert(bodyRefs.size >= 3, `request bodies name their schema files: ${[...bodyRefs]}`);
    for (const ref of bodyRefs) {
      const first = Object.values(load(ref).properties)[0];
      // view.schema.json's properties are allOf a $ref into request.schema.json: one more file.
      const description = first.description ?? load(first.allOf[0].$ref).description;
      assert(description && text.includes(description), `${ref} is resolved and drawn ("${description}")`);
    }

    const origin = new URL(server.url).origin;
    const elsewhere = requests.filter((u) => !u.startsWith("data:") && !u.startsWith("blob:") && new URL(u).origin !== origin);
    assert(elsewhere.length === 0, `nothing is fetched from another origin: ${elsewhere.join(", ")}`);
    assert(refused.length === 0, `the policy refused nothing: ${refused.join(" | ")}`);
    fs.mkdirSync(outDir, { recursive: true });
    await page.screenshot({ path: path.join(outDir, "docs_page.png") });
  },
};

const body = scenarios[scenario];
if (!binary || !outDir || !body) {
  console.error(`usage: docs_page.mjs ROOMRENDER OUT_DIR (${Object.keys(scenarios).join("|")})`);
  process.exit(2);
}
process.exit(await runScenario(scenario, { binary, outDir }, body));
