// JSON Schema checks as the user types. In: the server's own schemas (GET /v1/schemas/{name}.json,
// so the page checks exactly what the server accepts) and a parsed request. Out: a short list of
// {pointer, message}, one per real problem, instead of the validator's full trace (which repeats
// every failure at each enclosing allOf/$ref/properties and once per oneOf branch).
import { Validator } from "@cfworker/json-schema";

// A pointer from the validator's "#/a/b" instance locations (already escaped as JSON Pointers).
const toPointer = (location) => decodeURIComponent(location.replace(/^#/, ""));

// Keywords that only say "something below failed": the failure below is reported by itself.
const wrappers = new Set(["properties", "items", "prefixItems", "allOf", "$ref", "anyOf", "oneOf", "false",
  "contains", "unevaluatedProperties", "dependentSchemas", "if", "then", "else", "not"]);

// Items of one array share keyword locations, so a branch is told apart by its instance too.
const within = (location, instance) => location === instance || location.startsWith(instance + "/");

// Which branches of each failed oneOf are beside the point. A branch that fails on the instance's
// type (a colour given as a string is not the array branch) or on the discriminating `type`
// member (a box is not a cylinder) was never the one meant; the errors of the others are the
// useful ones. When every branch is ruled out that way, one summary error replaces them all.
function pruneOneOf(errors) {
  const excluded = [];
  const summaries = [];
  for (const e of errors) {
    if (e.keyword !== "oneOf") continue;
    const base = e.keywordLocation + "/";
    const instance = e.instanceLocation;
    const branches = new Map();
    for (const f of errors) {
      if (!f.keywordLocation.startsWith(base) || !within(f.instanceLocation, instance)) continue;
      const index = f.keywordLocation.slice(base.length).split("/")[0];
      if (!branches.has(index)) branches.set(index, []);
      branches.get(index).push(f);
    }
    const ruledOut = [];
    const wanted = [];
    for (const [index, list] of branches) {
      const discriminator = list.find((f) =>
        (f.keyword === "type" && f.instanceLocation === instance) ||
        (f.keyword === "const" && f.instanceLocation === instance + "/type"));
      if (discriminator) {
        ruledOut.push(index);
        const m = /"([^"]*)"\.?$/.exec(discriminator.error);
        if (m) wanted.push(m[1]);
      }
    }
    for (const index of ruledOut) excluded.push({ keyword: `${base}${index}/`, instance });
    if (ruledOut.length > 0 && ruledOut.length === branches.size) {
      const typeError = branches.values().next().value.find((f) => f.keyword === "const");
      summaries.push(typeError
        ? { pointer: toPointer(instance + "/type"), message: `"type" must be one of ${wanted.map((w) => `"${w}"`).join(", ")}` }
        : { pointer: toPointer(instance), message: `must be one of the types ${wanted.join(", ")}` });
    }
  }
  const kept = errors.filter((e) =>
    !excluded.some((x) => e.keywordLocation.startsWith(x.keyword) && within(e.instanceLocation, x.instance)));
  return { kept, summaries };
}

function describe(e) {
  if (e.keyword === "additionalProperties") {
    const m = /Property "(.*)" does not match/.exec(e.error);
    if (m) return { pointer: toPointer(e.instanceLocation) + "/" + m[1].replace(/~/g, "~0").replace(/\//g, "~1"),
      message: `unknown member "${m[1]}"` };
  }
  if (e.keyword === "required") {
    const m = /required property "(.*)"/.exec(e.error);
    if (m) return { pointer: toPointer(e.instanceLocation), message: `needs "${m[1]}"` };
  }
  return { pointer: toPointer(e.instanceLocation), message: e.error.replace(/^Instance /, "") };
}

export function summarizeErrors(errors) {
  const { kept, summaries } = pruneOneOf(errors);
  const out = [...summaries];
  for (const e of kept) {
    if (wrappers.has(e.keyword)) continue;
    out.push(describe(e));
  }
  const seen = new Set();
  return out.filter((d) => {
    const key = d.pointer + "\u0000" + d.message;
    if (seen.has(key)) return false;
    seen.add(key);
    return true;
  });
}

// schemas: the request schema first, then those it references (scene.schema.json).
export function makeRequestChecker(requestSchema, ...referenced) {
  const validator = new Validator(requestSchema, "2020-12", false);
  for (const s of referenced) validator.addSchema(s);
  return (request) => {
    const result = validator.validate(request);
    return result.valid ? [] : summarizeErrors(result.errors);
  };
}
