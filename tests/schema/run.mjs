// Schema test: schemas/ checked with a real JSON Schema validator (ajv, draft 2020-12) and against
// the real server. Every example request must validate; over the corpus (corpus.mjs) the server
// must accept exactly what the schema accepts, except the listed semantic rules a schema cannot
// state, which the schema accepts and the server refuses with 422. Answers are validated too: JSON
// renders, problem bodies, stored-scene receipts. OpenAPI references must resolve, and the document's
// request examples must be accepted.
//   node run.mjs BUILD/roomrender REPOSITORY_ROOT
import Ajv2020 from "ajv/dist/2020.js";
import { spawn } from "node:child_process";
import { readFileSync, readdirSync } from "node:fs";
import { createInterface } from "node:readline";
import { base, cases } from "./corpus.mjs";

const [binary, repo] = process.argv.slice(2);
if (!binary || !repo) {
  console.error("usage: node run.mjs BUILD/roomrender REPOSITORY_ROOT");
  process.exit(2);
}

// Each schema's $id is its file name, so relative $refs resolve beside it, on disk and on a server.
const ID = "";
// strict mode refuses schemas that are ambiguous or use unknown keywords; allowUnionTypes permits
// type arrays; the content* keywords are annotations in 2020-12.
const ajv = new Ajv2020({ strict: true, allowUnionTypes: true });
for (const file of readdirSync(`${repo}/schemas`).filter((f) => f.endsWith(".schema.json"))) {
  ajv.addSchema(JSON.parse(readFileSync(`${repo}/schemas/${file}`, "utf8")));
}
const schema = (name) => {
  const validate = ajv.getSchema(`${ID}${name}.schema.json`);
  if (!validate) throw new Error(`schema ${name} not loaded`);
  return validate;
};

let passed = 0;
let failed = 0;
function check(ok, what, details = "") {
  if (ok) {
    passed += 1;
  } else {
    failed += 1;
    console.log(`FAIL ${what}${details ? `\n     ${details}` : ""}`);
  }
}
const errorsOf = (validate) => ajv.errorsText(validate.errors);

// --- the server ----------------------------------------------------------------------------------
const server = spawn(binary, ["serve", "--port", "0", "--log-requests", "0"], { stdio: ["ignore", "pipe", "inherit"] });
const firstLine = await new Promise((resolve, reject) => {
  const lines = createInterface({ input: server.stdout });
  lines.once("line", resolve);
  server.once("exit", (code) => reject(new Error(`server exited with ${code}`)));
});
const origin = `http://127.0.0.1:${JSON.parse(firstLine).port}`;

async function send(method, path, body, accept) {
  const headers = { "Content-Type": "application/json" };
  if (accept) headers.Accept = accept;
  const res = await fetch(origin + path, { method, headers, body: body === undefined ? undefined : JSON.stringify(body) });
  const type = res.headers.get("content-type") || "";
  const bytes = Buffer.from(await res.arrayBuffer());
  return { status: res.status, type, text: bytes.toString("utf8"), headers: res.headers };
}

// The served tables and the schema's enums name the same values in the same order: a row added to a
// table without the schema (or the reverse) fails here as well as in the unit test.
const table = JSON.parse((await send("GET", "/v1/pipelines")).text);
const options = JSON.parse(readFileSync(`${repo}/schemas/request.schema.json`, "utf8")).$defs.options.properties;
for (const [what, served, listed] of [
  ["pipelines", table.pipelines.map((p) => p.name), options.pipeline.enum],
  ["shading modes", table.shading, options.shading.enum],
]) {
  check(JSON.stringify(served) === JSON.stringify(listed), `GET /v1/pipelines ${what} equal the schema's enum`,
        `served ${JSON.stringify(served)}, schema ${JSON.stringify(listed)}`);
}

function checkProblem(answer, what) {
  check(answer.type === "application/problem+json", `${what}: problem media type`, answer.type);
  const problem = JSON.parse(answer.text);
  const validate = schema("problem");
  check(validate(problem), `${what}: problem body matches problem.schema.json`, errorsOf(validate));
  check(problem.status === answer.status, `${what}: problem status repeats the HTTP status`);
}

// --- every example validates, and renders ---------------------------------------------------------
const request = schema("request");
const examples = readdirSync(`${repo}/examples`).filter((f) => f.endsWith(".json"));
for (const file of examples) {
  const example = JSON.parse(readFileSync(`${repo}/examples/${file}`, "utf8"));
  check(request(example), `example ${file} validates`, errorsOf(request));
  // Rendered small: the size is not what is being tested.
  const small = structuredClone(example);
  small.options = { ...(small.options || {}), width: 48, height: 36 };
  cases.push({ kind: "valid", name: `example ${file}`, request: small });
}

// --- the corpus: both judges agree ---------------------------------------------------------------
for (const c of cases) {
  const schemaOk = request(c.request);
  const schemaErrors = errorsOf(request);
  const answer = await send("POST", "/v1/render", c.request);
  const serverOk = answer.status === 200;
  const summary = `schema ${schemaOk ? "accepts" : "rejects"} (${schemaOk ? "" : schemaErrors}), server ${answer.status} ${serverOk ? "" : answer.text}`;
  if (c.kind === "valid") {
    check(schemaOk && serverOk, `valid case "${c.name}" accepted by both`, summary);
  } else if (c.kind === "invalid") {
    check(!schemaOk && [400, 413, 422].includes(answer.status), `invalid case "${c.name}" rejected by both`, summary);
  } else if (c.kind === "semantic") {
    check(schemaOk && answer.status === 422, `semantic case "${c.name}": schema accepts, server 422`, summary);
  } else {
    check(schemaOk && answer.status === 413, `limit case "${c.name}": schema accepts, server 413`, summary);
  }
  if (!serverOk) checkProblem(answer, `case "${c.name}"`);
}

// --- answers match their schemas -----------------------------------------------------------------
const rendered = await send("POST", "/v1/render", base, "application/json");
const renderResponse = schema("render-response");
check(rendered.status === 200 && renderResponse(JSON.parse(rendered.text)), "JSON render answer matches render-response.schema.json",
      errorsOf(renderResponse));

const stored = await send("POST", "/v1/scenes", base.scene);
const receipt = schema("scene-stored");
const storedBody = JSON.parse(stored.text);
check([200, 201].includes(stored.status) && receipt(storedBody), "stored-scene receipt matches scene-stored.schema.json",
      `${stored.status} ${errorsOf(receipt)}`);
const fetched = await send("GET", storedBody.location);
check(schema("scene")(JSON.parse(fetched.text)), "a stored scene read back validates against scene.schema.json");

const view = schema("view");
const goodView = { camera: base.camera, options: base.options };
check(view(goodView), "a view validates against view.schema.json", errorsOf(view));
check((await send("POST", `${storedBody.location}/render`, goodView)).status === 200, "the server renders that view");
const badView = { scene: base.scene, camera: base.camera };
check(!view(badView), "a view carrying a scene is rejected by view.schema.json");
const refused = await send("POST", `${storedBody.location}/render`, badView);
check(refused.status === 422, "and by the server", `${refused.status}`);
checkProblem(refused, "view with a scene");

const sceneSchema = schema("scene");
const badScene = { ...base.scene, sky: "#000000" };
check(!sceneSchema(badScene), "an unknown scene key is rejected by scene.schema.json");
const badStore = await send("POST", "/v1/scenes", badScene);
check(badStore.status === 422, "and by POST /v1/scenes", `${badStore.status} ${badStore.text}`);

// --- the OpenAPI document's references resolve ---------------------------------------------------
const openapi = JSON.parse((await send("GET", "/openapi.json")).text);
check(/^3\.1\./.test(openapi.openapi), "OpenAPI version is 3.1.x", openapi.openapi);
const refs = [];
(function collect(node) {
  if (Array.isArray(node)) node.forEach(collect);
  else if (node && typeof node === "object") {
    for (const [key, value] of Object.entries(node)) {
      if (key === "$ref") refs.push(value);
      else collect(value);
    }
  }
})(openapi);
for (const ref of new Set(refs)) {
  const match = /^\/v1\/schemas\/([a-z0-9_-]+)\.schema\.json(#.*)?$/.exec(ref);
  const resolved = match && ajv.getSchema(`${ID}${match[1]}.schema.json${match[2] || ""}`);
  check(Boolean(resolved), `OpenAPI $ref ${ref} resolves to a served schema`);
  if (match) check((await send("GET", `/v1/schemas/${match[1]}.schema.json`)).status === 200, `${ref} is served`);
}

// --- the OpenAPI document's request examples are accepted --------------------------------------
// The examples openapi.json shows (and /docs with it) are sent as they are (an externalValue as the
// bytes the server serves there); an import example is
// named by the {format} it is for, and PUT's {id} is the one POST gave the same scene.
const document = JSON.parse(readFileSync(`${repo}/schemas/openapi.json`, "utf8"));
const storedIds = [];
for (const [path, item] of Object.entries(document.paths)) {
  for (const [method, op] of Object.entries(item)) {
    for (const [type, media] of Object.entries(op.requestBody?.content || {})) {
      for (const [name, example] of Object.entries(media.examples || {})) {
        let url = path.replace("{format}", name);
        if (url.includes("{id}")) url = url.replace("{id}", storedIds.at(-1) || "0000000000000000");
        const json = type.endsWith("json");
        // A binary body (an image) is shown by externalValue, a path this server serves: its bytes are sent.
        const value = example.externalValue
          ? Buffer.from(await (await fetch(origin + example.externalValue)).arrayBuffer())
          : example.value;
        const res = await fetch(origin + url, {
          method: method.toUpperCase(),
          headers: { "Content-Type": type },
          body: json ? JSON.stringify(value) : value,
        });
        const body = await res.arrayBuffer();
        check(res.ok, `openapi example ${name} of ${method.toUpperCase()} ${path} (${type}) is accepted`,
              `${res.status} ${Buffer.from(body).toString("utf8").slice(0, 300)}`);
        if (res.ok && path === "/v1/scenes" && method === "post") storedIds.push(JSON.parse(Buffer.from(body).toString("utf8")).id);
      }
    }
  }
}

server.kill("SIGTERM");
const exitCode = await new Promise((resolve) => server.once("exit", resolve));
check(exitCode === 0, "server exits 0 on SIGTERM", `${exitCode}`);

console.log(`schema: ${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
