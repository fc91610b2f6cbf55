// OpenAPI test, offline: schemas/openapi.json is validated as a file on disk by swagger-parser
// (the OpenAPI 3.1 schema plus its own rules), with HTTP resolution switched off so every $ref must
// resolve to a file beside it. Then the conventions: relative $refs and $ids, servers, and an
// example for every request body, each JSON example valid against its schema (ajv, 2020-12).
//   node openapi.mjs REPOSITORY_ROOT
import SwaggerParser from "@apidevtools/swagger-parser";
import Ajv2020 from "ajv/dist/2020.js";
import { readFileSync, readdirSync } from "node:fs";

const [repo] = process.argv.slice(2);
if (!repo) {
  console.error("usage: node openapi.mjs REPOSITORY_ROOT");
  process.exit(2);
}
const dir = `${repo}/schemas`;

let passed = 0;
let failed = 0;
function check(ok, what, details = "") {
  if (ok) passed += 1;
  else {
    failed += 1;
    console.log(`FAIL ${what}${details ? `\n     ${details}` : ""}`);
  }
}

// A scheme or a leading slash ties a reference to one place; a relative one resolves wherever the
// files sit together (a checkout, /v1/schemas/ on a server, a copy on someone's disk).
const isRelative = (uri) => !/^[a-z][a-z0-9+.-]*:/i.test(uri) && !uri.startsWith("/");

function collect(node, key, out = []) {
  if (Array.isArray(node)) node.forEach((n) => collect(n, key, out));
  else if (node && typeof node === "object") {
    for (const [k, v] of Object.entries(node)) {
      if (k === key && typeof v === "string") out.push(v);
      else collect(v, key, out);
    }
  }
  return out;
}

// --- valid, resolved from disk alone ---------------------------------------------------------------
try {
  await SwaggerParser.validate(`${dir}/openapi.json`, { resolve: { http: false } });
  check(true, "swagger-parser validates schemas/openapi.json offline");
} catch (error) {
  check(false, "swagger-parser validates schemas/openapi.json offline", error.message);
}

const openapi = JSON.parse(readFileSync(`${dir}/openapi.json`, "utf8"));
for (const ref of new Set(collect(openapi, "$ref"))) check(isRelative(ref), `openapi.json $ref ${ref} is relative`);

const ajv = new Ajv2020({ strict: true, allowUnionTypes: true });
for (const file of readdirSync(dir).filter((f) => f.endsWith(".schema.json"))) {
  const schema = JSON.parse(readFileSync(`${dir}/${file}`, "utf8"));
  check(schema.$id === file, `${file}: $id is its own file name, so its $refs resolve beside it`, schema.$id);
  for (const ref of new Set(collect(schema, "$ref"))) check(isRelative(ref), `${file}: $ref ${ref} is relative`);
  ajv.addSchema(schema);
}

// --- servers and info --------------------------------------------------------------------------------
check(Array.isArray(openapi.servers) && openapi.servers.length > 0, "servers lists at least one server");
for (const server of openapi.servers || []) check(typeof server.url === "string" && server.description, `server ${server.url} has a url and a description`);
check(openapi.info?.title && openapi.info?.version && openapi.info?.license?.name, "info has a title, a version and a licence");

// --- every request body has examples, and JSON examples validate ----------------------------------
const methods = ["get", "put", "post", "delete", "patch", "head", "options"];
let bodies = 0;
for (const [path, item] of Object.entries(openapi.paths)) {
  for (const method of methods.filter((m) => item[m]?.requestBody)) {
    bodies += 1;
    const where = `${method.toUpperCase()} ${path}`;
    const content = item[method].requestBody.content;
    const withExamples = Object.entries(content).filter(([, media]) => Object.keys(media.examples || {}).length > 0);
    check(withExamples.length > 0, `${where}: the request body has an example`);
    for (const [type, media] of Object.entries(content)) {
      if (!type.endsWith("json")) continue;
      check(withExamples.some(([t]) => t === type), `${where}: ${type} has an example`);
      // A body is one schema file, or oneOf several (POST /v1/scenes: a scene or a whole request).
      const refs = media.schema?.oneOf ? media.schema.oneOf.map((s) => s.$ref) : [media.schema?.$ref];
      const validators = refs.map((ref) => ref && ajv.getSchema(ref));
      check(validators.every(Boolean), `${where}: ${type} schema ${refs.join(" | ")} is schema files`);
      for (const [name, example] of Object.entries(media.examples || {})) {
        const matching = validators.filter((validate) => validate && validate(example.value));
        check(matching.length === 1, `${where}: example ${name} matches exactly one of ${refs.join(" | ")}`,
              `${matching.length} match`);
      }
    }
  }
}
check(bodies > 0, "the document has request bodies to check", `${bodies}`);

console.log(`openapi: ${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
