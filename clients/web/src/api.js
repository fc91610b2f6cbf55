// The page's view of the roomrender HTTP API (docs/api.md). In: request objects; out: plain results
// ({imageBlob, timings, counts, warnings, sceneId, cache}) or a thrown ApiError holding the server's
// problem+json. Endpoints newer than the first server (OpenAPI document, JSON render answers,
// schemas, importers) are detected at run time, so the page works against either.
export class ApiError extends Error {
  constructor(status, problem) {
    super(problem.detail || problem.title || `HTTP ${status}`);
    this.status = status;
    this.problem = problem;
    // Field errors with JSON Pointers into the request; a problem without them is about the whole body.
    this.errors = Array.isArray(problem.errors) && problem.errors.length
      ? problem.errors.map((e) => ({ pointer: e.pointer ?? "", detail: e.detail ?? "", parameter: e.parameter }))
      : [{ pointer: null, detail: this.message }];
  }
}

async function problemOf(res) {
  const type = res.headers.get("Content-Type") || "";
  const retryAfter = Number(res.headers.get("Retry-After")) || null;
  if (type.includes("json")) {
    try {
      return { ...(await res.json()), retryAfter };
    } catch {
      // fall through: a broken body still has a status
    }
  }
  return { status: res.status, title: res.statusText, detail: `The server answered HTTP ${res.status}.`, retryAfter };
}

// What a refusal that is not about the request means, in plain words with what to do (null: the
// answer's own errors say it, by pointer). The flags named are `roomrender serve`'s.
export function plainWords(error) {
  if (error?.status === 507) {
    return "The server's store is full, so it did not keep this scene (it never throws stored scenes away " +
      "to make room). Delete scenes you no longer need in Your scenes, or ask whoever runs the server to raise " +
      "--scene-store-bytes or --scene-store-entries (--mesh-store-bytes, --mesh-store-entries for meshes). " +
      "Renders that need no storing still work.";
  }
  if (error?.status === 401) {
    return "This server stores and deletes scenes only for an access token (it runs with --api-token-file): " +
      "enter yours under Your scenes, then try again.";
  }
  if (error?.status === 503) {
    const wait = error.problem?.retryAfter ? `in ${error.problem.retryAfter} s` : "in a few seconds";
    return "The server is too busy right now: every render slot is taken and its queue is full (or it is " +
      `shutting down, or its store does not answer). Nothing is wrong with the scene: try again ${wait}. ` +
      "If it keeps happening, ask whoever runs the server to raise --render-queue or --render-workers " +
      "(or --store-timeout-ms when its store is a database).";
  }
  return null;
}

async function ok(res) {
  if (!res.ok) throw new ApiError(res.status, await problemOf(res));
  return res;
}

// "parse;dur=0.12, tessellate;dur=1.5" -> {parse: 0.12, tessellate: 1.5}, in header order.
export function parseServerTiming(header) {
  const out = {};
  for (const entry of (header || "").split(",")) {
    const [name, ...params] = entry.trim().split(";").map((s) => s.trim());
    if (!name) continue;
    const dur = params.find((p) => p.startsWith("dur="));
    out[name] = dur ? Number(dur.slice(4)) : NaN;
  }
  return out;
}

function base64ToBlob(base64, type) {
  const bytes = Uint8Array.from(atob(base64), (c) => c.charCodeAt(0));
  return new Blob([bytes], { type });
}

export class Api {
  constructor(base = "") {
    this.base = base;
    this.paths = null;  // OpenAPI paths once known; null: the server has no OpenAPI document
    this.token = null;  // bearer token sent with writes and listings (a server with --api-token-file)
  }

  // The headers of a write (or a listing): `headers` with the bearer token when there is one.
  authorized(headers = {}) {
    return this.token ? { ...headers, Authorization: `Bearer ${this.token}` } : headers;
  }

  url(path) {
    return this.base + path;
  }

  async getJson(path, init) {
    return (await ok(await fetch(this.url(path), init))).json();
  }

  // Learns which endpoints exist. A server without /openapi.json is the first one: render only.
  async detect() {
    try {
      const res = await fetch(this.url("/openapi.json"));
      this.paths = res.ok ? (await res.json()).paths || {} : null;
    } catch {
      this.paths = null;
    }
    return this;
  }

  has(path, method = "post") {
    return Boolean(this.paths && this.paths[path] && this.paths[path][method]);
  }

  hasParameter(path, name, method = "post") {
    return Boolean(this.has(path, method) && (this.paths[path][method].parameters || []).some((p) => p.name === name));
  }

  pipelines() {
    return this.getJson("/v1/pipelines");
  }

  // GET /v1/catalogue: the furniture catalogue ({items: [{id, name, category, size_cm, icon, piece}],
  // attribution}), or null from a server without one.
  async catalogue() {
    return this.has("/v1/catalogue", "get") ? this.getJson("/v1/catalogue") : null;
  }

  // GET /v1/catalogue/textures: the texture catalogue ({textures: [{id, catalog_id, name, category,
  // size_cm, pixels, url}], attribution}), or null from a server without one.
  async textureCatalogue() {
    return this.has("/v1/catalogue/textures", "get") ? this.getJson("/v1/catalogue/textures") : null;
  }

  // POST /v1/textures: stores a PNG or JPEG file -> {id, width, height, ...}.
  async storeTexture(file, { signal } = {}) {
    const res = await fetch(this.url("/v1/textures"), {
      method: "POST",
      headers: this.authorized({ "Content-Type": file.type || "application/octet-stream", Accept: "application/json" }),
      body: file,
      signal,
    });
    if (!res.ok) throw scopedError(res.status, await problemOf(res));
    return res.json();
  }

  async examples() {
    return (await this.getJson("/examples/")).examples || [];
  }

  async exampleText(name) {
    return (await ok(await fetch(this.url(`/examples/${encodeURIComponent(name)}.json`)))).text();
  }

  // The request schema and the schemas it references, or null when the server does not publish them.
  async requestSchemas() {
    const get = async (name) => {
      const res = await fetch(this.url(`/v1/schemas/${name}.json`));
      return res.ok ? res.json() : null;
    };
    const [request, scene] = await Promise.all([get("request.schema"), get("scene.schema")]);
    return request && scene ? [request, scene] : null;
  }

  // POST /v1/render. Asks for JSON (timings, counts, warnings with the image) but takes the PNG answer
  // of a server that does not offer JSON, reading the same facts from its headers.
  render(body, { signal } = {}) {
    return this.renderAt("/v1/render", body, { signal });
  }

  // POST /v1/scenes/{id}/render with {camera, options}: as render(), for a stored scene. Its
  // warnings point into the stored scene (/solids/3); they are given as pointers into the request.
  async renderStored(id, view, { signal } = {}) {
    const result = await this.renderAt(`/v1/scenes/${encodeURIComponent(id)}/render`, view, { signal, stored: true });
    const scoped = (w) => ({ ...w, pointer: sceneScoped(w.pointer), ...(w.other ? { other: sceneScoped(w.other) } : {}) });
    return { ...result, warnings: result.warnings.map(scoped) };
  }

  // POST /v1/pick: the element visible at pixel (x, y) of the request's image, {pointer, part, point,
  // depth, camera, ...} (pointer null on the background; part, the piece's part there); stored: POST /v1/scenes/{id}/pick with the
  // view, its pointer given as one into the request (/scene/solids/3).
  async pick(request, x, y, { storedId = null, signal } = {}) {
    const { scene, ...view } = request;
    const [path, body] = storedId ? [`/v1/scenes/${encodeURIComponent(storedId)}/pick`, { ...view, x, y }]
      : ["/v1/pick", { ...request, x, y }];
    const res = await fetch(this.url(path), {
      method: "POST", headers: { "Content-Type": "application/json", Accept: "application/json" },
      body: JSON.stringify(body), signal,
    });
    if (!res.ok) throw storedId ? scopedError(res.status, await problemOf(res)) : new ApiError(res.status, await problemOf(res));
    const answer = await res.json();
    if (!storedId || answer.pointer === null) return answer;
    const part = answer.part ? { ...answer.part, pointer: sceneScoped(answer.part.pointer) } : answer.part;
    return { ...answer, pointer: sceneScoped(answer.pointer), part };
  }

  async renderAt(path, body, { signal, stored = false } = {}) {
    const res = await fetch(this.url(path), {
      method: "POST",
      headers: { "Content-Type": "application/json", Accept: "application/json, image/png;q=0.5" },
      body: typeof body === "string" ? body : JSON.stringify(body),
      signal,
    });
    if (!res.ok && stored) throw scopedError(res.status, await problemOf(res));
    await ok(res);
    const type = res.headers.get("Content-Type") || "";
    if (type.startsWith("application/json")) {
      const answer = await res.json();
      return {
        imageBlob: base64ToBlob(answer.png_base64, "image/png"),
        timings: answer.timings_ms || {},
        counts: answer.counts || {},
        warnings: answer.warnings || [],
        warningCount: answer.warning_count ?? (answer.warnings || []).length,
        sceneId: answer.scene_id,
        cache: answer.cache,
        pipeline: answer.pipeline,
        camera: answer.camera ?? null,  // the camera drawn, when the request asked for a frame
      };
    }
    return {
      imageBlob: await res.blob(),
      timings: parseServerTiming(res.headers.get("Server-Timing")),
      counts: {},
      warnings: [],
      warningCount: Number(res.headers.get("X-Warning-Count") || 0),
      sceneId: res.headers.get("X-Scene-Id") || "",
      cache: res.headers.get("X-Cache") || "",
    };
  }

  // POST /v1/scenes: stores a scene document (an object, or its text as it is) -> {id, ...}.
  async storeScene(scene, { signal } = {}) {
    const res = await fetch(this.url("/v1/scenes"), {
      method: "POST",
      headers: this.authorized({ "Content-Type": "application/json", Accept: "application/json" }),
      body: typeof scene === "string" ? scene : JSON.stringify(scene),
      signal,
    });
    if (!res.ok) throw scopedError(res.status, await problemOf(res));
    return res.json();
  }

  // DELETE /v1/scenes/{id}.
  async deleteScene(id, { signal } = {}) {
    const res = await fetch(this.url(`/v1/scenes/${encodeURIComponent(id)}`), {
      method: "DELETE", headers: this.authorized(), signal,
    });
    if (!res.ok) throw new ApiError(res.status, await problemOf(res));
  }

  // GET /v1/scenes (or the `next` URL of a page before): a page of stored scenes, newest first,
  // {scenes: [{id, created, expires, bytes}], next}; with a token, its owner's.
  async listScenes(next = null, { signal } = {}) {
    const path = next ?? "/v1/scenes?limit=50";
    const res = await fetch(this.url(path), { headers: this.authorized({ Accept: "application/json" }), signal });
    return (await ok(res)).json();
  }

  // GET /v1/scenes/{id}: the stored scene document as text (canonical JSON).
  async storedSceneText(id, { signal } = {}) {
    return (await ok(await fetch(this.url(`/v1/scenes/${encodeURIComponent(id)}`), { signal }))).text();
  }

  // POST /v1/import/{format}: a file of another tool -> a complete render request (as text).
  async importFile(format, file, { signal } = {}) {
    const res = await ok(await fetch(this.url(`/v1/import/${encodeURIComponent(format)}`), {
      method: "POST",
      headers: { "Content-Type": "application/octet-stream", Accept: "application/json" },
      body: file,
      signal,
    }));
    return { text: await res.text(), warningCount: Number(res.headers.get("X-Warning-Count") || 0) };
  }

  // POST /v1/import/{format}?store=1: the file's scene is stored on the server, which answers its id
  // with the default camera and options ({id, camera, options, warnings}); the scene never travels
  // back as part of the answer. `models`: furniture=models, so that a home's furniture is drawn with
  // its models whatever the file (a bare Home.xml has none: the warnings then name those missing).
  // `scale`: metres per file unit (the importer's scale query parameter), null for the format's own.
  async importStored(format, file, { signal, models = false, scale = null } = {}) {
    const furniture = models && this.hasParameter("/v1/import/{format}", "furniture") ? "&furniture=models" : "";
    const scaled = scale ? `&scale=${encodeURIComponent(scale)}` : "";
    const res = await ok(await fetch(this.url(`/v1/import/${encodeURIComponent(format)}?store=1${furniture}${scaled}`), {
      method: "POST",
      headers: this.authorized({ "Content-Type": "application/octet-stream", Accept: "application/json" }),
      body: file,
      signal,
    }));
    return res.json();
  }
}

// A pointer into a stored scene document (/solids/3) as a pointer into a request (/scene/solids/3);
// those into the view of a stored render (/camera/…, /options/…) are request pointers already.
function sceneScoped(pointer) {
  if (typeof pointer !== "string" || !pointer.startsWith("/") || /^\/(camera|options)(\/|$)/.test(pointer)) return pointer;
  return `/scene${pointer}`;
}

function scopedError(status, problem) {
  const errors = Array.isArray(problem.errors)
    ? problem.errors.map((e) => ({ ...e, pointer: sceneScoped(e.pointer) })) : problem.errors;
  return new ApiError(status, { ...problem, errors });
}
