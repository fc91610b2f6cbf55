// Links to a stored scene: the page's permalink (/?scene=ID&view=…) and the image URL
// (GET /v1/scenes/{id}/render.png?…, docs/api.md). A stored scene has no camera, so the permalink
// carries the request's camera and options as JSON in `view`, exactly as they are (numbers keep
// every digit), and a page opened from it sends the same request. Pure functions; no DOM.

// The members of a request that are not the scene: what a view of a stored scene is made of.
export function viewOf(request) {
  const view = {};
  if (request && request.camera !== undefined) view.camera = request.camera;
  if (request && request.options !== undefined) view.options = request.options;
  return view;
}

export function permalink(origin, id, view) {
  return `${origin}/?scene=${encodeURIComponent(id)}&view=${encodeURIComponent(JSON.stringify(view))}`;
}

// {id, view} from a page URL's search part, or null when it names no stored scene. A `view` that is
// not a JSON object is an error the page shows (thrown, with the reason).
export function parsePermalink(search) {
  const params = new URLSearchParams(search);
  const id = params.get("scene");
  if (!id) return null;
  const text = params.get("view");
  if (text === null) return { id, view: {} };
  let view;
  try {
    view = JSON.parse(text);
  } catch (error) {
    throw new Error(`the link's view is not JSON (${error.message})`);
  }
  if (!view || typeof view !== "object" || Array.isArray(view)) throw new Error("the link's view is not a JSON object");
  return { id, view };
}

// render.png takes plain decimals: no exponent (1e-7), which JavaScript writes for small numbers.
function decimal(v) {
  const s = String(v);
  return /e/i.test(s) ? v.toFixed(20).replace(/\.?0+$/, "") : s;
}

const vector = (v) => v.map(decimal).join(",");

// Query parameter -> where its value is in the request, and how it is written (docs/api.md).
const queryMembers = [
  ["position", ["camera", "position"], vector], ["target", ["camera", "target"], vector], ["up", ["camera", "up"], vector],
  ["fov_y", ["camera", "fov_y"], decimal], ["near", ["camera", "near"], decimal], ["far", ["camera", "far"], decimal],
  ["width", ["options", "width"], decimal], ["height", ["options", "height"], decimal],
  ["pipeline", ["options", "pipeline"], String], ["shading", ["options", "shading"], String],
  ["shadows", ["options", "shadows"], String], ["painter_key", ["options", "painter", "key"], String],
  ...["w1", "w2", "w3", "epsilon", "max_candidates", "traversal"].map((k) => [`bsp_${k}`, ["options", "bsp", k], k === "traversal" ? String : decimal]),
  ...["size", "pcf", "bias", "slope_bias", "fit", "method"].map((k) => [`shadow_${k}`, ["options", "shadow", k], k === "fit" || k === "method" ? String : decimal]),
];

// The GET URL of the image of a stored scene seen with `view`: {url, missing}, where `missing` lists
// the view's members that have no query parameter (the URL's image would differ from the page's).
export function imageUrl(origin, id, view) {
  const params = [];
  const used = new Set();
  for (const [name, path, write] of queryMembers) {
    let v = view;
    for (const k of path) v = v && typeof v === "object" ? v[k] : undefined;
    if (v === undefined) continue;
    params.push(`${name}=${encodeURIComponent(write(v)).replace(/%2C/g, ",")}`);
    used.add(path.join("/"));
  }
  const missing = [];
  const walk = (value, path) => {
    if (value && typeof value === "object" && !Array.isArray(value)) {
      for (const [k, v] of Object.entries(value)) walk(v, [...path, k]);
    } else if (!used.has(path.join("/"))) {
      missing.push(`/${path.join("/")}`);
    }
  };
  walk(view, []);
  const query = params.length ? `?${params.join("&")}` : "";
  return { url: `${origin}/v1/scenes/${encodeURIComponent(id)}/render.png${query}`, missing };
}
