// roomrender's web page: the request editor on the left, the rendered image (or two pipelines and
// their difference) on the right. The editor's text is the one source of truth for the scene: the
// selectors and the designer edit it by JSON Pointer. Camera gestures move the designer's live
// camera, which reaches the text when the page is idle; they render the stored copy of the scene by
// id (sharing.js). At most one render (or compare pair) is in flight: a newer one aborts it, except
// while a drag goes on, when the newest camera waits for the answer in flight, so each is shown.
import { Api, ApiError, plainWords } from "./api.js";
import { RequestEditor } from "./editor.js";
import { makeRequestChecker } from "./schema_check.js";
import { withDefaults, orbit, pan, zoom, look } from "./camera.js";
import { attachViewer } from "./viewer.js";
import { drawTimingChart, formatMs } from "./timings.js";
import { showComparison, clearComparison } from "./compare_view.js";
import { Controls } from "./controls.js";
import { Designer, newRequest } from "./designer.js";
import { showWarningList } from "./warning_list.js";
import { showProblems, replaceImage, showStats, download } from "./result_view.js";
import { Sharing, storedSceneLink } from "./sharing.js";
import { parsePermalink, viewOf } from "./share.js";
import { bigSceneChars } from "./big_scene.js";
import { viewGrabber } from "./view_select.js";
import { YourScenes } from "./your_scenes.js";
import { missingModelsHint } from "./import_hint.js";

const $ = (id) => document.getElementById(id);
const defaultExample = "apartment";
const previewScale = 0.5;    // renders while dragging are this fraction of the size, each way
const restMs = 250;          // a drag that rests this long gets its full-size render

const api = new Api();
const app = {
  inflight: null,       // AbortController of the render in flight
  seq: 0,               // number of the latest render started
  shown: null,          // {blob, url, result} of the image on screen (A)
  shownB: null,
  loadedCamera: null,   // the camera of the loaded example: Home / 0 returns to it
  exampleName: "request",
  restTimer: 0,         // full-size render due after a drag rests
  planFrame: 0,         // reduced-size render of a plan drag due at the next frame
  planScene: null,
  inflightPreview: false,  // the render in flight is a drag's reduced-size one
  queued: null,         // the options of a drag's render waiting for the one in flight
  warnedScene: null,    // the scene whose warnings are shown: the same scene's answers repeat them
  loading: 0,           // examples, imports or the start-up being fetched: a render will follow
  busy: false,          // the progress bar shows (setBusy)
};

// Counts `work` (a promise-returning function) as loading while it runs, for idle().
async function loading(work) {
  app.loading++;
  try {
    return await work();
  } finally {
    app.loading--;
  }
}

const showProblemList = (items) => showProblems(items, (pointer) => editor.reveal(pointer));

// Touches the page only when the state changes: a drag's images end a render each, and every
// attribute written on the body restyles the page.
function setBusy(busy) {
  if (app.busy === busy) return;
  app.busy = busy;
  $("progress").hidden = !busy;
  document.body.toggleAttribute("data-busy", busy);
  $("render").setAttribute("aria-busy", String(busy));
}

// Writes a text only when it differs: replacing a text node lays the page out again.
function setText(element, text) {
  if (element.textContent !== text) element.textContent = text;
}

function setStatus(text) {
  $("status").textContent = text;
}

function showWarnings(result) {
  const notes = result.warnings.map((w) => ({ pointer: w.pointer, message: w.detail, severity: "warning" }));
  editor.setServerNotes(notes);
  app.lastWarnings = result.warnings;
  app.warningCount = result.warningCount || notes.length;
  designer.setMarks(result.warnings.map((w) => ({ ...w, severity: "warning" })));
  showProblemList([]);
  showWarningList(result.warnings, app.warningCount, warningClicks);
  return app.warningCount;
}

// How the warning list names an element: a solid by its id (an imported piece's is its name and
// where it was in the home), else its pointer.
function elementLabel(pointer) {
  const m = /^\/scene\/solids\/(\d+)$/.exec(pointer || "");
  const solid = m && designer.lastScene?.solids?.[Number(m[1])];
  return solid?.id ? `${solid.id} — ${pointer}` : pointer || "the scene";
}

function showError(error) {
  app.warnedScene = null;
  const plain = plainWords(error);
  if (plain) {
    // About the server, not a field: no mark in the editor or the plan; said where Save says it.
    showProblemList([{ pointer: null, detail: plain }]);
    sharing.showError(`HTTP ${error.status}: ${plain}`, { transient: true });
    if (error.status === 401) yourScenes.askToken();
  } else if (error instanceof ApiError) {
    editor.setServerNotes(error.errors.map((e) => ({ pointer: e.pointer, message: e.detail, severity: "error" })));
    showProblemList(error.errors.map((e) => ({ pointer: e.pointer, detail: e.detail })));
    designer.setMarks(error.errors.map((e) => ({ ...e, severity: "error" })));
    setStatus(`The server refused the request (HTTP ${error.status} ${error.problem.title || ""}).`);
  } else {
    showProblemList([{ pointer: null, detail: `Could not reach the server: ${error.message}` }]);
    setStatus("Render failed.");
  }
}

// `preview`: a reduced-size image while a drag goes on (the full size follows when it rests).
// `scene`: the scene as a plan drag shows it, not yet in the editor. `moved`: a camera move, which
// renders a stored copy of the scene by id (storing the working copy when none holds this scene).
function render(options = {}) {
  clearTimeout(app.restTimer);
  app.restTimer = 0;
  cancelAnimationFrame(app.planFrame);
  app.planFrame = 0;
  return launch(options);
}

async function launch({ preview = false, scene = null, moved = false } = {}) {
  const parsed = designer.request();
  const request = parsed && scene ? { ...parsed, scene } : parsed;
  if (request === null) {
    showProblemList([{ pointer: null, detail: "The request is not valid JSON yet; the editor marks where." }]);
    return;
  }
  // A drag's image waits for the one in flight rather than abort it: the server would draw the
  // aborted one anyway, and a drag that aborts each image shows none.
  if (preview && app.inflight && app.inflightPreview) {
    app.queued = { preview, scene, moved };
    return;
  }
  app.queued = null;
  if (app.inflight) app.inflight.abort();
  const controller = new AbortController();
  app.inflight = controller;
  app.inflightPreview = preview;
  const seq = ++app.seq;
  const started = performance.now();
  // A drag's images change neither the progress bar nor the status (each change would lay the page
  // out again); the image itself shows the progress.
  if (!preview) {
    setBusy(true);
    setStatus("Rendering…");
  }
  const compareWith = controls.comparePipeline();
  try {
    const requests = [request];
    if (compareWith) {
      requests.push({ ...request, options: { ...(request.options || {}), pipeline: compareWith } });
    }
    const small = (r) => {
      const o = r.options || {};
      const w = Math.max(1, Math.round((o.width ?? 640) * previewScale));
      const h = Math.max(1, Math.round((o.height ?? 480) * previewScale));
      return { ...r, options: { ...o, width: w, height: h } };
    };
    const results = await Promise.all(requests.map(async (r, i) =>
      (await sharing.render(preview ? small(r) : r, { signal: controller.signal, store: moved })) ??
        api.render(preview ? small(r) : i === 0 && !scene && !designer.cameraPending() ? editor.text() : r, { signal: controller.signal })));
    if (seq !== app.seq) return;
    await display(request, results, seq, { preview });
    const server = results.map((r) => formatMs(r.timings.total)).join(" + ");
    if (!preview) setStatus(`Rendered in ${formatMs(performance.now() - started)} (server: ${server}).`);
  } catch (error) {
    if (error.name === "AbortError" || seq !== app.seq) return;
    showError(error);
  } finally {
    if (seq === app.seq) {
      app.inflight = null;
      setBusy(false);
      if (app.queued) launch(app.queued);
    }
  }
}

async function display(request, [a, b], seq, { preview = false } = {}) {
  const pipelineA = request.options?.pipeline || "zbuffer";
  const img = $("image");
  const url = replaceImage(img, app.shown, a.imageBlob);
  app.shown = { blob: a.imageBlob, url, result: a, pipeline: pipelineA };
  await img.decode().catch(() => {});
  setText($("caption-a"), pipelineA);
  const series = [{ label: pipelineA, timings: a.timings }];
  if (b) {
    const imgB = $("image-b");
    app.shownB = { blob: b.imageBlob, url: replaceImage(imgB, app.shownB, b.imageBlob), result: b };
    await imgB.decode().catch(() => {});
    $("caption-b").textContent = controls.comparePipeline();
    series.push({ label: controls.comparePipeline(), timings: b.timings });
    await showComparison(img, imgB, $("diff"), $("metrics"), [pipelineA, controls.comparePipeline()]);
  } else {
    if ($("metrics").hasChildNodes()) clearComparison($("metrics"));
  }
  if (!preview) drawTimingChart($("timings"), series);
  // The same scene has the same warnings: a camera move redraws neither the notes nor the plan.
  if (request.scene !== app.warnedScene) {
    app.warningCount = showWarnings(a);
    app.warnedScene = request.scene;
  }
  if (!preview) showStats(a, app.warningCount);
  // Tests (and people) can tell a new image from the old one by this number.
  img.dataset.renderSeq = String(seq);
  $("views").dataset.renderSeq = String(seq);
  if (!preview) {
    sharing.showLinks(request);
    sharing.rendered();
  }
}

// Camera gestures move the designer's live camera (not the text), then render the stored scene from
// it: reduced size while a drag goes on, full size once it rests or ends. In walk mode a drag looks
// around (the eye stays).
function moveCamera(kind, ...args) {
  const request = designer.request();
  if (request === null) return;
  const camera = withDefaults(request.camera);
  const walking = designer.tool === "walk";
  const moved = kind === "orbit" ? (walking ? look : orbit)(camera, ...args)
    : kind === "pan" ? pan(camera, ...args) : zoom(camera, ...args);
  designer.viewCamera({ ...(request.camera || {}), position: moved.position, target: moved.target });
  if ($("views").classList.contains("dragging")) {
    render({ preview: true, moved: true });
    // At rest, the full size; a reduced image still on its way is not aborted for it (on a slow
    // server the preview of each step would be, and the drag would show nothing).
    const rest = () => {
      app.restTimer = app.inflight ? setTimeout(rest, 50) : 0;
      if (!app.restTimer) render({ moved: true });
    };
    app.restTimer = setTimeout(rest, restMs);
  } else {
    render({ moved: true });
  }
}

function endDrag() {
  if (app.restTimer) render({ moved: true });
}

function resetCamera() {
  if (!app.loadedCamera) return;
  designer.viewCamera(app.loadedCamera);
  render({ moved: true });
}

function loadExample(name) {
  return loading(() => loadExampleNow(name));
}

async function loadExampleNow(name) {
  try {
    const text = await api.exampleText(name);
    app.exampleName = name;
    designer.replaceAll(text, { render: false });
    const request = editor.parsed();
    app.example = { name, sceneKey: JSON.stringify(request?.scene) };
    controls.showExample(name);
    app.loadedCamera = request && request.camera ? request.camera : null;
    showProblemList([]);
    controls.readFrom(request);
    await render();
  } catch (error) {
    showError(error);
  }
}

// Files of other tools go through the server's importers; a .json file is a request already.
function importFile(file) {
  return loading(() => importFileNow(file));
}

// How a Sweet Home 3D home opens: its lamps come at the power its photo renderer gives them, which
// assumes shadows (without them every lamp lights every surface through the walls), so Phong with
// exact shadows, the fastest shadows on a home.
const homeLook = { shading: "phong", shadows: true, shadow: { method: "rays" } };

const noHome = (error) => /archive holds no home/.test([error.message, ...(error.errors || []).map((e) => e.detail)].join(" "));

async function importFileNow(file) {
  const format = controls.importFormat(file.name);
  showImportHint(null);
  try {
    setStatus(`Importing ${file.name}…`);
    if (format === "json") {
      const text = await file.text();
      if (text.length <= bigSceneChars) {
        designer.replaceAll(JSON.stringify(JSON.parse(text), null, 2), { render: false });
      } else {
        const request = JSON.parse(text);
        sharing.load(JSON.stringify(request.scene ?? {}), null, viewOf(request));
      }
    } else {
      // Stored by the server and rendered by id: an interior's meshes never travel back as JSON.
      const { scaleError, ...options } = controls.importOptions();
      if (format === "obj" && scaleError) {
        setStatus(`${scaleError} Nothing was imported: correct it under Import… and open the file again.`);
        return;
      }
      const look = format === "sh3d" ? homeLook : {};
      const receipt = await sharing.importStored(format, file, { ...options, scale: format === "obj" ? options.scale : null, look })
        .catch((error) => {
          // A zip of an OBJ and its .mtl, named like a home's: the server finds no home XML in it.
          if (format !== "sh3d" || !/\.zip$/i.test(file.name) || error.status !== 422 || !noHome(error)) throw error;
          return sharing.importStored("obj", file, options);
        });
      if (receipt.warnings?.length) setStatus(`Imported ${file.name} with ${receipt.warnings.length} repair(s).`);
      showImportHint(missingModelsHint(file.name, receipt.warnings));
      yourScenes.refreshIfOpen();
    }
    app.exampleName = file.name.replace(/\.[^.]*$/, "");
    const request = editor.parsed();
    app.loadedCamera = request?.camera || null;
    controls.readFrom(request);
    await render();
  } catch (error) {
    showError(error);
  }
}

function showImportHint(text) {
  $("import-hint").textContent = text || "";
  $("import-hint").hidden = !text;
}

// Opens a scene of Your scenes as the working scene, as a permalink opens one, with the current
// options and the server's frame of the whole scene (the stored document has no camera).
function openStored(id) {
  return loading(async () => {
    const options = designer.request()?.options ?? {};
    const scale = (n) => Math.max(16, Math.round(n / 4));
    const sample = { ...options, width: scale(options.width ?? 640), height: scale(options.height ?? 480) };
    const framed = api.has("/v1/scenes/{id}/render")
      ? await api.renderStored(id, { camera: { frame: "all" }, options: sample }).then((r) => r.camera, () => null) : null;
    showImportHint(null);
    sharing.showError(null);
    await sharing.openPermalink(id, { ...(framed ? { camera: framed } : {}), options });
    app.exampleName = `scene-${id}`;
    app.loadedCamera = editor.parsed()?.camera || null;
    controls.readFrom(editor.parsed());
    controls.showExample(null);
    setStatus(`Opened the stored scene ${id}.`);
    await render();
  });
}

const editor = new RequestEditor($("editor"), {
  onChange: () => {
    controls.readFromSoon(() => editor.parsed(), (request) => controls.showExample(
      app.example && JSON.stringify(request?.scene) === app.example.sceneKey ? app.example.name : null));
    designer.textChanged();
  },
  onRun: () => render(),
});
const designer = new Designer(editor, {
  onEdited: () => render(),
  onCameraMoved: ({ preview = false } = {}) => render({ moved: true, preview }),
  busy: () => $("views").classList.contains("dragging") || Boolean(designer.drag),
  onStatus: setStatus,
  imageUrl: (id) => api.url(`/v1/textures/${id}`),
  onSave: () => sharing.save().then((id) => {
    if (id) yourScenes.refreshIfOpen();
    return id;
  }),
  onReplaced: () => sharing.replaced(),
  autosaveText: () => sharing.autosaveText(),
  // A plan drag renders at reduced size, at most once a frame and once the last preview is drawn; a
  // big scene would be stored each step, so it waits for the drop.
  // Frame all asks the server for its frame of the scene (a JSON render with "frame": "all").
  frameCamera: (request) => loading(async () => {
    const { up, fov_y, near, far } = request.camera || {};
    const view = { ...request, camera: { frame: "all", up, fov_y, near, far } };
    const answer = (await sharing.render(view)) ?? (await api.render(view));
    return answer.camera;
  }),
  onDragPreview: (scene) => {
    app.planScene = scene;
    if (!scene || sharing.isBig()) {
      cancelAnimationFrame(app.planFrame);
      app.planFrame = 0;
    } else if (!app.planFrame) {
      // One preview at a time: the server draws what it was sent even when the page gives up on it,
      // so aborting one preview a frame would queue a render a frame (a second each on a furnished
      // home) until the server refuses them all, the drop's render too.
      const step = () => {
        app.planFrame = app.inflight ? requestAnimationFrame(step) : 0;
        if (!app.planFrame && app.planScene) render({ preview: true, scene: app.planScene });
      };
      app.planFrame = requestAnimationFrame(step);
    }
  },
});
const sharing = new Sharing({ api, editor, designer, onStatus: setStatus });
const yourScenes = new YourScenes({
  api,
  onOpen: openStored,
  onDeleted: (id) => sharing.forget(id),
  isHere: (id) => sharing.holds(id),
  onToken: () => sharing.mayStoreAgain(),
});
const warningClicks = { reveal: (p) => editor.reveal(p), select: (p) => designer.select(p), label: elementLabel };
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
  onDragEnd: endDrag,
  // With the Select tool a click on the image selects what the server's picking finds there, and a
  // drag that starts on a solid moves it.
  onGrab: viewGrabber({
    designer,
    img: $("image"),
    pick: (request, x, y) => loading(() => sharing.pick(request, x, y)),
    onError: (error) => showError(error),
    enabled: () => api.has("/v1/pick"),
  }),
});
$("warning-kind").addEventListener("change", () => showWarningList(app.lastWarnings || [], app.warningCount || 0, warningClicks));

// Hooks for scripted checks that drive the page as a person would (tests/browser/designer.mjs).
window.roomrenderDesigner = {
  worldToPlan: (x, z) => designer.plan.toClient(x, z),
  // The page point over the centre of pixel (u, v) of the full-size image, however large it is shown.
  viewToPage: (u, v) => {
    const r = $("image").getBoundingClientRect();
    const o = designer.request()?.options || {};
    const w = o.width ?? 640;
    const h = o.height ?? 480;
    return { x: r.left + ((u + 0.5) * r.width) / w, y: r.top + ((v + 0.5) * r.height) / h };
  },
  request: () => designer.request(),
  // The editor's text as it is (the camera reaches it once the page rests).
  text: () => editor.text(),
  selection: () => designer.selection,
  // The bytes of the PNG on screen, base64-encoded (null before the first render).
  png: async () => {
    if (!app.shown) return null;
    const bytes = new Uint8Array(await app.shown.blob.arrayBuffer());
    let binary = "";
    for (let i = 0; i < bytes.length; i += 0x8000) binary += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
    return btoa(binary);
  },
  idle: () => new Promise((resolve) => {
    const check = () => (app.inflight || app.restTimer || app.planFrame || app.loading ? setTimeout(check, 25) : resolve());
    check();
  }),
};

$("render").addEventListener("click", () => render());
$("example").addEventListener("change", (e) => {
  if (e.target.value) loadExample(e.target.value);
});
$("download-png").addEventListener("click", () => {
  if (app.shown) download(app.shown.blob, `${app.exampleName}-${app.shown.pipeline}.png`);
});
$("download-scene").addEventListener("click", () => {
  designer.syncCamera();
  const request = sharing.isBig() ? editor.parsed() : null;
  const text = request ? JSON.stringify({ ...request, scene: sharing.fullScene(request.scene || {}) }) : editor.text();
  download(new Blob([text], { type: "application/json" }), `${app.exampleName}.json`);
});
// The text shows the camera on screen before the user reads or types into it.
$("editor").addEventListener("focusin", () => designer.syncCamera());
document.querySelector('[data-action="new"]').addEventListener("click", () => showImportHint(null));
$("example").addEventListener("change", () => showImportHint(null));
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

// Opens a permalink (/?scene=ID&view=…): true when it named a scene and it loaded; a link that
// fails says why, visibly, and the page goes on as without it.
async function openLink(search) {
  let link;
  try {
    link = parsePermalink(search);
  } catch (error) {
    sharing.showError(`This link cannot be opened: ${error.message}.`);
    return false;
  }
  if (!link) return false;
  try {
    await sharing.openPermalink(link.id, link.view);
  } catch (error) {
    const why = error.status === 404 ? "the server has no such scene (it may have been evicted or deleted)"
      : error.message;
    sharing.showError(`Scene ${link.id} could not be opened: ${why}.`);
    return false;
  }
  app.exampleName = `scene-${link.id}`;
  app.loadedCamera = editor.parsed()?.camera || null;
  controls.readFrom(editor.parsed());
  controls.showExample(null);
  setStatus(`Opened the stored scene ${link.id}.`);
  await render();
  return true;
}

async function start() {
  await api.detect();
  const [pipelines, examples, schemas] = await Promise.all([
    api.pipelines().catch(() => ({ pipelines: [{ name: "zbuffer" }] })),
    api.examples().catch(() => []),
    api.has("/v1/schemas/{name}.json", "get") ? api.requestSchemas().catch(() => null) : null,
  ]);
  controls.setPipelines(pipelines);
  controls.setImportSupported(api.has("/v1/import/{format}"));
  designer.setCatalogue(await api.catalogue().catch(() => null));
  designer.setTextures(await api.textureCatalogue().catch(() => null), api.has("/v1/textures") ? (file) => api.storeTexture(file) : null);
  if (schemas) {
    editor.setChecker(sharing.filterChecker(makeRequestChecker(...schemas)));
    $("check-note").textContent = "Checked against the server's schema as you type; Ctrl+Enter renders.";
  } else {
    $("check-note").textContent =
      "This server does not publish its schemas (GET /v1/schemas/{name}.json), so the server checks on render; Ctrl+Enter renders.";
  }
  const wanted = new URLSearchParams(location.search).get("example");
  const first = examples.includes(wanted) ? wanted : examples.includes(defaultExample) ? defaultExample : examples[0];
  controls.setExamples(examples, first);
  if (await openLink(location.search)) return;
  const saved = wanted ? null : Designer.saved();
  const savedLink = storedSceneLink(saved);
  if (savedLink && (await openLink(savedLink))) return;
  if (saved && !savedLink) {
    designer.replaceAll(saved, { render: false });
    designer.history.reset(editor.text());
    designer.updateButtons();
    app.loadedCamera = editor.parsed()?.camera || null;
    controls.readFrom(editor.parsed());
    setStatus("Restored the scene saved in this browser.");
    await render();
  } else if (first) {
    await loadExample(first);
  } else {
    designer.replaceAll(JSON.stringify(newRequest(), null, 2));
  }
}

loading(start).catch((error) => showError(error));
