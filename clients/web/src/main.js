// roomrender's web page: the request editor on the left, the rendered image (or two pipelines and
// their difference) on the right. The editor's text is the one source of truth: the selectors and
// camera gestures edit it by JSON Pointer, and every render sends it as it is. At most one render
// (or compare pair) is in flight: a newer one aborts it.
import { Api, ApiError } from "./api.js";
import { RequestEditor } from "./editor.js";
import { makeRequestChecker } from "./schema_check.js";
import { withDefaults, orbit, pan, zoom } from "./camera.js";
import { attachViewer } from "./viewer.js";
import { drawTimingChart, formatMs } from "./timings.js";
import { showComparison, clearComparison } from "./compare_view.js";
import { Controls } from "./controls.js";

const $ = (id) => document.getElementById(id);
const defaultExample = "apartment";

const api = new Api();
const app = {
  inflight: null,       // AbortController of the render in flight
  seq: 0,               // number of the latest render started
  shown: null,          // {blob, url, result} of the image on screen (A)
  shownB: null,
  loadedCamera: null,   // the camera of the loaded example: Home / 0 returns to it
  exampleName: "request",
};

function showProblems(items) {
  const list = $("problems");
  list.replaceChildren();
  for (const { pointer, detail, severity } of items) {
    const li = document.createElement("li");
    li.className = severity || "error";
    if (pointer !== null && pointer !== undefined) {
      const link = document.createElement("button");
      link.type = "button";
      link.className = "pointer";
      link.textContent = pointer === "" ? "(whole request)" : pointer;
      link.title = "Show this field in the editor";
      link.addEventListener("click", () => editor.reveal(pointer));
      li.append(link, " ");
    }
    li.append(detail);  // text, never HTML: details can quote the request
    list.append(li);
  }
}

function setBusy(busy) {
  $("progress").hidden = !busy;
  document.body.toggleAttribute("data-busy", busy);
  $("render").setAttribute("aria-busy", String(busy));
}

function setStatus(text) {
  $("status").textContent = text;
}

function replaceImage(img, previous, blob) {
  if (previous) URL.revokeObjectURL(previous.url);
  const url = URL.createObjectURL(blob);
  img.src = url;
  return url;
}

function showStats(result, warningCount) {
  const counts = result.counts || {};
  const rows = [
    ["scene id", result.sceneId],
    ["BSP cache", result.cache],
    ["polygons", counts.polygons],
    ["polygons drawn", counts.polygons_drawn],
    ["fragments", counts.fragments],
    ["placement warnings", warningCount],
  ].filter(([, v]) => v !== undefined && v !== "");  // a PNG answer carries fewer facts than JSON
  $("stats").replaceChildren(...rows.flatMap(([k, v]) => {
    const dt = document.createElement("dt");
    dt.textContent = k;
    const dd = document.createElement("dd");
    dd.textContent = String(v);
    return [dt, dd];
  }));
}

// Places the answer's placement warnings (and the count of a PNG answer, whose list is not sent).
function showWarnings(result) {
  const notes = result.warnings.map((w) => ({ pointer: w.pointer, message: w.detail, severity: "warning" }));
  editor.setServerNotes(notes);
  const items = notes.map((n) => ({ pointer: n.pointer, detail: n.message, severity: "warning" }));
  if (!notes.length && result.warningCount) {
    items.push({ pointer: null, detail: `${result.warningCount} placement warning(s); this server lists them only in JSON answers.`, severity: "warning" });
  }
  showProblems(items);
  return notes.length || result.warningCount || 0;
}

function showError(error) {
  if (error instanceof ApiError) {
    editor.setServerNotes(error.errors.map((e) => ({ pointer: e.pointer, message: e.detail, severity: "error" })));
    showProblems(error.errors.map((e) => ({ pointer: e.pointer, detail: e.detail })));
    setStatus(`The server refused the request (HTTP ${error.status} ${error.problem.title || ""}).`);
  } else {
    showProblems([{ pointer: null, detail: `Could not reach the server: ${error.message}` }]);
    setStatus("Render failed.");
  }
}

async function render() {
  const request = editor.parsed();
  if (request === null) {
    showProblems([{ pointer: null, detail: "The request is not valid JSON yet; the editor marks where." }]);
    return;
  }
  if (app.inflight) app.inflight.abort();
  const controller = new AbortController();
  app.inflight = controller;
  const seq = ++app.seq;
  const started = performance.now();
  setBusy(true);
  setStatus("Rendering…");
  const compareWith = controls.comparePipeline();
  try {
    const requests = [request];
    if (compareWith) {
      requests.push({ ...request, options: { ...(request.options || {}), pipeline: compareWith } });
    }
    const results = await Promise.all(requests.map((r, i) =>
      api.render(i === 0 ? editor.text() : r, { signal: controller.signal })));
    if (seq !== app.seq) return;
    await display(request, results, seq);
    const server = results.map((r) => formatMs(r.timings.total)).join(" + ");
    setStatus(`Rendered in ${formatMs(performance.now() - started)} (server: ${server}).`);
  } catch (error) {
    if (error.name === "AbortError" || seq !== app.seq) return;
    showError(error);
  } finally {
    if (seq === app.seq) {
      app.inflight = null;
      setBusy(false);
    }
  }
}

async function display(request, [a, b], seq) {
  const pipelineA = request.options?.pipeline || "zbuffer";
  const img = $("image");
  const url = replaceImage(img, app.shown, a.imageBlob);
  app.shown = { blob: a.imageBlob, url, result: a, pipeline: pipelineA };
  await img.decode().catch(() => {});
  $("caption-a").textContent = pipelineA;
  const series = [{ label: pipelineA, timings: a.timings }];
  if (b) {
    const imgB = $("image-b");
    app.shownB = { blob: b.imageBlob, url: replaceImage(imgB, app.shownB, b.imageBlob), result: b };
    await imgB.decode().catch(() => {});
    $("caption-b").textContent = controls.comparePipeline();
    series.push({ label: controls.comparePipeline(), timings: b.timings });
    await showComparison(img, imgB, $("diff"), $("metrics"), [pipelineA, controls.comparePipeline()]);
  } else {
    clearComparison($("metrics"));
  }
  drawTimingChart($("timings"), series);
  showStats(a, showWarnings(a));
  // Tests (and people) can tell a new image from the old one by this number.
  img.dataset.renderSeq = String(seq);
  $("views").dataset.renderSeq = String(seq);
}

// Camera gestures edit the request's camera, then render.
function moveCamera(kind, ...args) {
  const request = editor.parsed();
  if (request === null) return;
  const camera = withDefaults(request.camera);
  const moved = kind === "orbit" ? orbit(camera, ...args) : kind === "pan" ? pan(camera, ...args) : zoom(camera, ...args);
  editor.setValues([{ pointer: "/camera/position", value: moved.position }, { pointer: "/camera/target", value: moved.target }]);
  render();
}

function resetCamera() {
  if (!app.loadedCamera) return;
  editor.setValues([{ pointer: "/camera", value: app.loadedCamera }]);
  render();
}

async function loadExample(name) {
  try {
    const text = await api.exampleText(name);
    app.exampleName = name;
    editor.setText(text);
    const request = editor.parsed();
    app.loadedCamera = request && request.camera ? request.camera : null;
    showProblems([]);
    controls.readFrom(request);
    await render();
  } catch (error) {
    showError(error);
  }
}

function download(blob, name) {
  const a = document.createElement("a");
  a.href = URL.createObjectURL(blob);
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

// Files of other tools go through the server's importers; a .json file is a request already.
async function importFile(file) {
  const format = controls.importFormat(file.name);
  try {
    setStatus(`Importing ${file.name}…`);
    let text;
    if (format === "json") {
      text = await file.text();
    } else {
      const imported = await api.importFile(format, file);
      text = imported.text;
      if (imported.warningCount) setStatus(`Imported ${file.name} with ${imported.warningCount} repair(s).`);
    }
    app.exampleName = file.name.replace(/\.[^.]*$/, "");
    editor.setText(JSON.stringify(JSON.parse(text), null, 2));
    const request = editor.parsed();
    app.loadedCamera = request?.camera || null;
    controls.readFrom(request);
    await render();
  } catch (error) {
    showError(error);
  }
}

const editor = new RequestEditor($("editor"), {
  onChange: () => controls.readFromSoon(() => editor.parsed()),
  onRun: () => render(),
});
const controls = new Controls({
  setOptions: (entries) => {
    if (editor.setValues(entries)) render();
  },
  onCompareChange: () => {
    document.body.classList.toggle("comparing", Boolean(controls.comparePipeline()));
    render();
  },
});

attachViewer($("views"), {
  onMove: moveCamera,
  onReset: resetCamera,
  onToggleCompare: () => controls.toggleCompare(),
});

$("render").addEventListener("click", () => render());
$("example").addEventListener("change", (e) => loadExample(e.target.value));
$("download-png").addEventListener("click", () => {
  if (app.shown) download(app.shown.blob, `${app.exampleName}-${app.shown.pipeline}.png`);
});
$("download-scene").addEventListener("click", () => {
  download(new Blob([editor.text()], { type: "application/json" }), `${app.exampleName}.json`);
});
$("open-file").addEventListener("click", () => $("file").click());
$("file").addEventListener("change", (e) => {
  if (e.target.files[0]) importFile(e.target.files[0]);
  e.target.value = "";
});
document.addEventListener("keydown", (e) => {
  if (e.key === "Enter" && (e.ctrlKey || e.metaKey)) {
    e.preventDefault();
    render();
  } else if (e.key === "Escape" && app.inflight) {
    app.inflight.abort();
    setStatus("Render cancelled.");
  }
});

async function start() {
  await api.detect();
  const [pipelines, examples, schemas] = await Promise.all([
    api.pipelines().catch(() => ({ pipelines: [{ name: "zbuffer" }] })),
    api.examples().catch(() => []),
    api.has("/v1/schemas/{name}.json", "get") ? api.requestSchemas().catch(() => null) : null,
  ]);
  controls.setPipelines(pipelines);
  controls.setImportSupported(api.has("/v1/import/{format}"));
  if (schemas) {
    editor.setChecker(makeRequestChecker(...schemas));
    $("check-note").textContent = "Checked against the server's schema as you type; Ctrl+Enter renders.";
  } else {
    $("check-note").textContent =
      "This server does not publish its schemas (GET /v1/schemas/{name}.json), so the server checks on render; Ctrl+Enter renders.";
  }
  const wanted = new URLSearchParams(location.search).get("example");
  const first = examples.includes(wanted) ? wanted : examples.includes(defaultExample) ? defaultExample : examples[0];
  controls.setExamples(examples, first);
  if (first) await loadExample(first);
}

start().catch((error) => showError(error));
