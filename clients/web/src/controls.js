// The toolbar's selectors (pipeline, shading, shadows, size, anti-aliasing, exposure, compare) and the examples list. They
// mirror the request's options: reading the request sets them, and changing one calls
// setOptions([{pointer, value}]), which edits the request. Pipelines and shading modes come from
// GET /v1/pipelines, so a pipeline added to the server's table appears here by itself.
const $ = (id) => document.getElementById(id);

const sizes = [[320, 240], [640, 480], [800, 600], [1024, 768], [1280, 720], [1920, 1080]];
const fallbackShading = ["flat", "gouraud", "phong"];
// The exposure slider moves in stops (the multiplier is 2^stops); "auto" leaves the choice to the server.
const exposureLabel = (stops) => `${Number((2 ** stops).toPrecision(3))}×`;
const importFormats = { xml: "sh3d", sh3d: "sh3d", zip: "sh3d", obj: "obj", txt: "r2v", json: "json" };

function fillSelect(select, entries, value) {
  select.replaceChildren(...entries.map(([v, label, title]) => {
    const option = new Option(label, v);
    if (title) option.title = title;
    return option;
  }));
  if (value !== undefined) select.value = value;
}

export class Controls {
  constructor({ setOptions, onCompareChange }) {
    const setOption = (pointer, value) => setOptions([{ pointer, value }]);
    this.pipelines = [];
    this.timer = 0;
    $("import-units").addEventListener("change", (e) => { $("import-scale").hidden = e.target.value !== "custom"; });
    $("pipeline").addEventListener("change", (e) => setOption("/options/pipeline", e.target.value));
    $("shading").addEventListener("change", (e) => setOption("/options/shading", e.target.value));
    $("shadows").addEventListener("change", (e) => setOption("/options/shadows", e.target.checked));
    $("shadow-method").addEventListener("change", (e) => setOption("/options/shadow/method", e.target.value));
    $("size").addEventListener("change", (e) => {
      const [w, h] = e.target.value.split("x").map(Number);
      setOptions([{ pointer: "/options/width", value: w }, { pointer: "/options/height", value: h }]);
    });
    $("antialias").addEventListener("change", (e) => setOption("/options/antialias", Number(e.target.value)));
    $("exposure").addEventListener("input", (e) => { $("exposure-value").value = exposureLabel(Number(e.target.value)); });
    $("exposure").addEventListener("change", (e) => setOption("/options/exposure", 2 ** Number(e.target.value)));
    $("exposure-auto").addEventListener("change", (e) => {
      $("exposure").disabled = e.target.checked;
      setOption("/options/exposure", e.target.checked ? "auto" : 2 ** Number($("exposure").value));
    });
    $("compare").addEventListener("change", onCompareChange);
    $("pipeline-b").addEventListener("change", () => { if ($("compare").checked) onCompareChange(); });
    this.onCompareChange = onCompareChange;
  }

  setPipelines({ pipelines, shading }) {
    this.pipelines = pipelines.map((p) => p.name);
    const entries = pipelines.map((p) => [p.name, p.name, p.summary]);
    fillSelect($("pipeline"), entries, "zbuffer");
    // The ground truth, when the server has one, is the natural thing to compare against.
    const b = this.pipelines.includes("reference") ? "reference" : this.pipelines.includes("zbuffer") ? "zbuffer" : this.pipelines[0];
    fillSelect($("pipeline-b"), entries, b);
    const modes = Array.isArray(shading) && shading.length ? shading : fallbackShading;
    fillSelect($("shading"), modes.map((m) => [m, m]), "flat");
  }

  setExamples(names, selected) {
    fillSelect($("example"), names.map((n) => [n, n.replace(/_/g, " ")]), selected);
  }

  // The example selector names the example whose scene the editor holds, or "(custom)" once the
  // scene is another (New, a drawing, an import, a link). Picking "(custom)" loads nothing.
  showExample(name) {
    const select = $("example");
    let custom = select.querySelector('option[value=""]');
    if (name === null && !custom) {
      custom = new Option("(custom)", "");
      select.prepend(custom);
    }
    if (name !== null && custom) custom.remove();
    select.value = name ?? "";
  }

  setImportSupported(supported) {
    $("open-file").disabled = false;
    $("file").accept = supported ? ".json,.xml,.sh3d,.zip,.obj,.txt" : ".json";
    $("open-file").title = supported
      ? "Open a request (.json) or import a Sweet Home 3D home (.xml, .sh3d, or a .zip of its XML and furniture/), an OBJ model (.obj, or a .zip of it and its .mtl) or an R2V plan (.txt)"
      : "Open a request (.json). Importing other formats needs POST /v1/import/{format}, which this server lacks.";
  }

  // The import options: {models} (a home's furniture as models, else boxes), {scale} (metres per
  // unit of an OBJ; null keeps the format's own) and {scaleError}: why a custom factor that is not a
  // number above 0 cannot be used (null when it can), also marked on the field.
  importOptions() {
    const units = $("import-units").value;
    const field = $("import-scale");
    const factor = Number(field.value);
    const custom = units === "custom";
    const usable = Number.isFinite(factor) && factor > 0;
    field.toggleAttribute("aria-invalid", custom && !usable);
    const scaleError = custom && !usable
      ? `The custom scale "${field.value}" is not a number of metres per unit above 0.` : null;
    const scale = custom ? (usable ? factor : null) : units ? Number(units) : null;
    return { models: $("import-furniture").value === "models", scale, scaleError };
  }

  // A .zip is taken for a home with its furniture unless named *.obj.zip (the import retries a zip
  // that holds no home as an OBJ).
  importFormat(fileName) {
    if (/\.obj\.zip$/i.test(fileName)) return "obj";
    const ext = (/\.([^.]+)$/.exec(fileName) || [])[1]?.toLowerCase();
    return importFormats[ext] || "sh3d";
  }

  // Sets the selectors from a parsed request (defaults as in docs/scene-format.md).
  readFrom(request) {
    if (!request || typeof request !== "object") return;
    const o = request.options && typeof request.options === "object" ? request.options : {};
    const pipeline = o.pipeline || "zbuffer";
    if (this.pipelines.includes(pipeline)) $("pipeline").value = pipeline;
    if ([...$("shading").options].some((opt) => opt.value === (o.shading || "flat"))) $("shading").value = o.shading || "flat";
    $("shadows").checked = o.shadows === true;
    $("shadow-method").value = o.shadow?.method === "rays" ? "rays" : "map";
    $("antialias").value = String([1, 4, 8, 16].includes(o.antialias) ? o.antialias : 1);
    const auto = o.exposure === "auto";
    const stops = typeof o.exposure === "number" && o.exposure > 0 ? Math.min(4, Math.max(-4, Math.log2(o.exposure))) : 0;
    $("exposure-auto").checked = auto;
    $("exposure").disabled = auto;
    if (!auto) $("exposure").value = String(stops);
    $("exposure-value").value = auto ? "auto" : exposureLabel(Number($("exposure").value));
    const key = `${o.width ?? 640}x${o.height ?? 480}`;
    const entries = sizes.map(([w, h]) => [`${w}x${h}`, `${w} × ${h}`]);
    if (!entries.some(([v]) => v === key)) entries.push([key, key.replace("x", " × ")]);
    fillSelect($("size"), entries, key);
  }

  // Typing changes the request many times a second; the selectors follow when it pauses.
  readFromSoon(parse, after = () => {}) {
    clearTimeout(this.timer);
    this.timer = setTimeout(() => {
      const request = parse();
      this.readFrom(request);
      if (request) after(request);
    }, 150);
  }

  comparePipeline() {
    return $("compare").checked ? $("pipeline-b").value : null;
  }

  toggleCompare() {
    $("compare").checked = !$("compare").checked;
    this.onCompareChange();
  }
}
