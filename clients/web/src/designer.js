// The room designer: tools that edit the request through the plan (walls, doors, windows, furniture,
// lights, select/move/rotate/delete/duplicate), a properties panel, undo/redo and autosave. In: the
// request editor (its text stays the one source of truth) and pointer/key events. Out: edits made by
// JSON Pointer through the editor, one history step each. The history holds whole request texts;
// a JSON text edit becomes one step once it has rested (or before the next designer action), and
// camera moves are not steps: undo keeps the camera where it is. A moving camera lives here
// (`liveCamera`, over the text's) and reaches the text once the page is idle or the editor is
// focused: a camera step parses, writes and checks no text. The plan's pointer tools are in
// designer_tools.js; the commands on the selection, the camera and the keys in designer_commands.js.
import { PlanView } from "./plan_view.js";
import { renderProperties, fieldProblem } from "./properties.js";
import { History } from "./history.js";
import { tools, toolMethods } from "./designer_tools.js";
import { commandMethods } from "./designer_commands.js";
import { at, setAt, clone } from "./designer_util.js";
import { catalogueEntries, categories } from "./catalogue.js";
import { paletteEntries, uploadedEntry } from "./textures.js";
import { bodyRadiusM } from "./visitor.js";
import { sceneLevels, levelsToDraw, levelShown, levelLabel } from "./levels.js";

const $ = (id) => document.getElementById(id);
const storageKey = "roomrender.designer.request";
const textStepDelayMs = 600;
const cameraTextDelayMs = 400;  // a camera at rest this long is written into the text

export const newRequest = () => ({
  scene: {
    version: 1,
    background: "#c9d6e3",
    ambient: { color: "#ffffff", intensity: 0.3 },
    walls: [],
    solids: [],
    lights: [{ type: "directional", direction: [-0.4, -1, -0.3], intensity: 0.8 }],
  },
  camera: { position: [2.5, 7, 10], target: [2.5, 0, 2], fov_y: 60 },
  options: { width: 640, height: 480 },
});

export class Designer {
  constructor(editor, { onEdited, onStatus, onSave = null, onReplaced = () => {}, autosaveText = null,
    onDragPreview = () => {}, frameCamera = async () => null, busy = () => false, onCameraMoved = onEdited,
    imageUrl = (id) => `/v1/textures/${id}` }) {
    this.editor = editor;
    this.onEdited = onEdited;      // a designer edit was applied: render
    this.onStatus = onStatus;
    this.onSave = onSave;          // Save was pressed (after the browser's copy was written)
    this.onReplaced = onReplaced;  // a whole new text is about to be loaded
    this.autosaveText = autosaveText;  // what the browser keeps (null: not this text), default the text
    this.onDragPreview = onDragPreview;  // (scene) while a plan drag moves an element; null when it ends
    this.frameCamera = frameCamera;  // async (request) -> the server's frame of the scene, or null
    this.onCameraMoved = onCameraMoved;  // the camera moved (walk, framing): render
    this.busy = busy;              // true while a gesture goes on: the camera's text waits for its end
    this.plan = new PlanView($("plan"));
    this.plan.imageUrl = imageUrl;
    this.tool = "select";
    this.item = "box";
    this.catalogue = new Map();    // the server's catalogue entries by id (catalogue.js)
    this.textures = new Map();     // the palette's textures by stored image id (textures.js)
    this.textureId = null;         // the texture the Texture tool puts on (null: none picked yet)
    this.selection = null;
    this.level = null;             // the level tab chosen (levels.js), null: All
    this.chain = [];               // wall tool: points clicked so far
    this.cursor = null;
    this.drag = null;
    this.marks = new Map();
    this.clashes = [];             // [{from, to, detail}]: pairs of elements a warning names
    this.history = new History(editor.text());
    this.applying = false;
    this.parsedDoc = null;
    this.parsedValue = null;
    this.liveCamera = null;        // the camera shown when it is not yet the text's (null: the text's)
    this.withCamera = null;        // parsedValue with liveCamera, built once per pair
    this.cameraTimer = 0;
    this.redrawFrame = 0;
    this.textTimer = 0;
    this.saveTimer = 0;
    this.lastScene = { walls: [], solids: [], lights: [] };
    this.bindToolbar();
    this.bindPlan();
    document.addEventListener("keydown", (e) => this.onKey(e), true);
    new ResizeObserver(() => this.redraw()).observe(this.plan.svg);
  }

  // ---- the request ---------------------------------------------------------------------------

  // The parsed request with the live camera, kept while the text is the same (the editor's document is
  // immutable, so its identity tells): the plan redraws on every pointer move, and an imported home's
  // text takes a while to parse. Callers treat it as read-only (edit() copies).
  request() {
    const doc = this.editor.doc();
    if (doc !== this.parsedDoc) {
      this.parsedDoc = doc;
      this.parsedValue = this.editor.parsed();
      this.withCamera = null;
    }
    const parsed = this.parsedValue;
    if (!parsed || !this.liveCamera) return parsed;
    if (this.withCamera?.camera !== this.liveCamera) this.withCamera = { ...parsed, camera: this.liveCamera };
    return this.withCamera;
  }

  // A camera move: shown at once (the plan's camera mark, and the caller renders), written into the
  // text later (syncCamera).
  viewCamera(camera) {
    this.liveCamera = camera;
    this.plan.placeCamera(camera);
    clearTimeout(this.cameraTimer);
    const later = () => {
      this.cameraTimer = setTimeout(() => {
        this.cameraTimer = 0;
        if (this.busy()) later();
        else if (window.requestIdleCallback) this.cameraTimer = requestIdleCallback(() => this.syncCamera(), { timeout: 1000 });
        else this.syncCamera();
      }, cameraTextDelayMs);
    };
    later();
  }

  // True while the camera shown is not yet written into the text.
  cameraPending() {
    return this.liveCamera !== null;
  }

  // Writes the live camera into the text: the members that differ, by pointer (the rest of the text
  // stays as typed), or the whole camera when its members differ.
  syncCamera() {
    clearTimeout(this.cameraTimer);
    if (window.cancelIdleCallback) cancelIdleCallback(this.cameraTimer);
    this.cameraTimer = 0;
    const camera = this.liveCamera;
    if (!camera) return;
    this.liveCamera = null;
    const written = this.request()?.camera;
    const keys = (c) => Object.keys(c || {}).sort().join();
    const entries = written && keys(written) === keys(camera)
      ? Object.keys(camera).filter((k) => JSON.stringify(camera[k]) !== JSON.stringify(written[k]))
        .map((k) => ({ pointer: `/camera/${k}`, value: camera[k] }))
      : [{ pointer: "/camera", value: camera }];
    if (entries.length) this.setCamera(entries);
  }

  // Writes `text` through the editor without it counting as a text edit.
  applyText(text) {
    this.applying = true;
    try {
      this.editor.replaceText(text);
    } finally {
      this.applying = false;
    }
  }

  applyValues(entries) {
    this.applying = true;
    try {
      return this.editor.setValues(entries);
    } finally {
      this.applying = false;
    }
  }

  // The editor's text changed. Designer writes are steps already; typing becomes one when it rests.
  textChanged() {
    this.scheduleSave();
    if (this.applying) return;
    clearTimeout(this.textTimer);
    this.textTimer = setTimeout(() => this.flushTextStep(), textStepDelayMs);
    if (!this.redrawFrame) {
      this.redrawFrame = requestAnimationFrame(() => {
        this.redrawFrame = 0;
        this.redraw();
      });
    }
  }

  flushTextStep() {
    clearTimeout(this.textTimer);
    this.textTimer = 0;
    this.history.settle(this.editor.text(), this.request() !== null);
    this.updateButtons();
  }

  // One designer step: `mutate(request)` edits a copy; the members it changed are written back by
  // pointer (so the rest of the text stays as typed). Returns false when nothing changed.
  edit(mutate) {
    this.flushTextStep();
    const before = this.request();
    if (before === null) {
      this.onStatus("The JSON has an error; fix it before editing in the plan.");
      return false;
    }
    const after = clone(before);
    after.scene = after.scene || {};
    const result = mutate(after);
    if (result === false) return false;
    const entries = [];
    if (!before.scene) {
      entries.push({ pointer: "/scene", value: after.scene });
    } else {
      for (const key of Object.keys(after.scene)) {
        if (JSON.stringify(before.scene[key]) !== JSON.stringify(after.scene[key])) {
          entries.push({ pointer: `/scene/${key}`, value: after.scene[key] });
        }
      }
    }
    if (!entries.length) return false;
    const text = this.editor.text();
    if (!this.applyValues(entries)) return false;
    this.history.record(text, this.editor.text());
    this.afterEdit();
    return true;
  }

  afterEdit() {
    this.updateButtons();
    this.redraw();
    this.showProperties();
    this.onEdited();
  }

  // Camera moves (orbit, walk, framing) edit the text but are no history step.
  setCamera(entries) {
    const wasCommitted = this.editor.text() === this.history.committed;
    const ok = this.applyValues(entries);
    if (ok && wasCommitted) this.history.amend(this.editor.text());
    this.redraw();
    return ok;
  }

  // A whole new request (New, an example, an import, a restore): one step, the plan fitted to it.
  // `step: false`: the new text stands in for the current one (the same scene, arrived in full).
  replaceAll(text, { render = true, step = true } = {}) {
    this.flushTextStep();
    this.liveCamera = null;
    this.onReplaced();
    const before = this.editor.text();
    this.editor.serverNotes = [];
    this.applyText(text);
    if (before === "") this.history.reset(this.editor.text());
    else if (!step) this.history.amend(this.editor.text());
    else this.history.record(before, this.editor.text());
    this.selection = null;
    this.chain = [];
    this.marks = new Map();
    this.clashes = [];
    const request = this.request();
    this.plan.fit(request?.scene);
    this.updateButtons();
    this.redraw();
    this.showProperties();
    if (render) this.onEdited();
  }

  // A history step back (or forward); the camera stays where it is.
  step(back) {
    this.flushTextStep();
    this.syncCamera();
    const camera = this.request()?.camera;
    const current = this.editor.text();
    const text = back ? this.history.back(current) : this.history.forward(current);
    if (text === null) return;
    this.applyText(text);
    if (camera && this.request()) this.applyValues([{ pointer: "/camera", value: camera }]);
    this.history.amend(this.editor.text());
    if (this.selection && at(this.request() || {}, this.selection) === undefined) this.selection = null;
    this.chain = [];
    this.afterEdit();
  }

  updateButtons() {
    document.querySelector('[data-action="undo"]').disabled = !this.history.undo.length;
    document.querySelector('[data-action="redo"]').disabled = !this.history.redo.length;
  }

  scheduleSave() {
    clearTimeout(this.saveTimer);
    this.saveTimer = setTimeout(() => this.save(), 400);
  }

  save() {
    clearTimeout(this.saveTimer);
    const text = this.autosaveText ? this.autosaveText() : this.editor.text();
    if (text === null) return;
    try {
      localStorage.setItem(storageKey, text);
    } catch {
      // storage full or disabled: autosave is a convenience
    }
  }

  static saved() {
    try {
      return localStorage.getItem(storageKey);
    } catch {
      return null;
    }
  }

  // ---- drawing -------------------------------------------------------------------------------

  redraw() {
    const request = this.request();
    if (request) this.lastScene = request.scene || {};
    if (request) this.followLevels(request);
    try {
      this.plan.draw(this.drag?.scene || this.lastScene, {
        level: this.level,
        selection: this.selection,
        marks: this.marks,
        clashes: this.clashes,
        preview: tools[this.tool].preview?.(this) ?? null,
        camera: request?.camera,
      });
    } catch (error) {
      // A request that parses but is not a scene yet (typing): the plan keeps what it could draw.
      console.debug("plan:", error);
    }
  }

  // The level tabs follow the request: a tab whose storeys are what options.levels draws stays
  // chosen; otherwise (a text edit, an undo, another scene) the tab is the one the request shows.
  followLevels(request) {
    const scene = request.scene || {};
    const levels = sceneLevels(scene);
    const drawn = Array.isArray(request.options?.levels) ? request.options.levels : levelsToDraw(scene, null);
    if (this.level !== null && !levels.some((l) => l.id === this.level)) this.level = null;
    if (JSON.stringify(levelsToDraw(scene, this.level)) !== JSON.stringify(drawn)) this.level = levelShown(request);
    const bar = $("levels");
    bar.hidden = levels.length === 0;
    const key = JSON.stringify([levels.map((l) => l.id), this.level]);
    if (bar.dataset.key === key) return;
    bar.dataset.key = key;
    bar.replaceChildren(...[{ id: null, label: "All levels" }, ...levels.map((l) => ({ id: l.id, label: levelLabel(l) }))].map(({ id, label }) => {
      const b = document.createElement("button");
      b.type = "button";
      b.setAttribute("role", "tab");
      b.setAttribute("aria-selected", String(id === this.level));
      b.dataset.level = id ?? "";
      b.textContent = label;
      b.title = id === null ? "Every viewable level in the image and every element in the plan"
        : `${id} and the levels below it in the image; its elements in the plan, where new ones go`;
      b.addEventListener("click", () => this.setLevel(id));
      return b;
    }));
  }

  // Chooses the level tab `id` (null: All): options.levels draws it and the levels below it.
  setLevel(id) {
    const request = this.request();
    if (!request) return;
    this.flushTextStep();
    this.level = id;
    const text = this.editor.text();
    if (this.applyValues([{ pointer: "/options/levels", value: levelsToDraw(request.scene || {}, id) }])) {
      this.history.record(text, this.editor.text());
    }
    this.selection = null;
    this.afterEdit();
  }

  // What a new element takes from the chosen level: its tag, and its floor as the base height.
  levelMembers() {
    const level = sceneLevels(this.lastScene).find((l) => l.id === this.level);
    return level ? { level: level.id, elevation: level.elevation ?? 0 } : null;
  }

  fit() {
    this.plan.fit(this.request()?.scene);
    this.redraw();
  }

  // Warnings and errors of the last answer, drawn on the elements they name ({pointer, detail,
  // severity}), and the pairs they name (a warning's `other`: what an element intersects) joined by a
  // line in the plan.
  setMarks(notes) {
    this.marks = new Map();
    this.clashes = [];
    const element = (pointer) => /^\/scene\/(walls\/\d+(\/openings\/\d+)?|solids\/\d+|lights\/\d+|floor)/.exec(pointer || "")?.[0];
    for (const n of notes) {
      const pointer = element(n.pointer);
      if (!pointer) continue;
      const old = this.marks.get(pointer);
      this.marks.set(pointer, {
        severity: old?.severity === "error" || n.severity === "error" ? "error" : "warning",
        text: old ? `${old.text}\n${n.detail}` : n.detail,
      });
      const other = element(n.other);
      if (other) this.clashes.push({ from: pointer, to: other, detail: n.detail });
    }
    this.redraw();
  }

  // ---- tools ---------------------------------------------------------------------------------

  setTool(tool) {
    const previous = this.tool;
    if (tool !== previous) tools[previous].leave?.(this);
    this.tool = tool;
    this.plan.visitor = tool === "walk" ? { radiusM: bodyRadiusM } : null;
    $("visitor-panel").hidden = tool !== "walk";
    for (const b of document.querySelectorAll("[data-tool]")) b.setAttribute("aria-pressed", String(b.dataset.tool === tool));
    $("catalogue").classList.toggle("inactive", tool !== "furniture");
    $("texture-palette").classList.toggle("inactive", tool !== "texture");
    document.body.dataset.tool = tool;
    if (tool !== previous) tools[tool].enter?.(this);
    this.redraw();
  }

  setItem(item) {
    this.item = item;
    for (const b of document.querySelectorAll("[data-item]")) b.setAttribute("aria-pressed", String(b.dataset.item === item));
  }

  // The server's catalogue (GET /v1/catalogue, or null): a category selector and a button per model
  // of the chosen category, its icon with its name and real size as the title.
  setCatalogue(answer) {
    this.catalogue = catalogueEntries(answer);
    const select = $("catalogue-category");
    const names = categories(this.catalogue);
    select.replaceChildren(...names.map((c) => new Option(c, c)));
    $("catalogue-models").hidden = !names.length;
    const show = () => {
      const buttons = [...this.catalogue.values()].filter((e) => e.category === select.value).map((e) => {
        const b = document.createElement("button");
        b.type = "button";
        b.dataset.item = e.id;
        const { width, depth, height } = e.size_cm;
        b.title = `${e.name}, ${width} × ${depth} cm, ${height} cm high`;
        b.setAttribute("aria-label", e.name);
        const img = document.createElement("img");
        img.src = e.icon;
        img.alt = "";
        b.append(img);
        b.addEventListener("click", () => {
          this.setItem(e.id);
          this.setTool("furniture");
        });
        return b;
      });
      $("catalogue-items").replaceChildren(...buttons);
      this.setItem(this.item);
    };
    select.onchange = show;
    show();
  }

  // The texture palette: a button per texture of the server's catalogue (GET /v1/catalogue/textures,
  // or null), and an upload when `upload` (async (file) -> POST /v1/textures's answer) is given; an
  // uploaded image joins the palette, chosen. Choosing one takes up the Texture tool.
  setTextures(answer, upload) {
    for (const e of paletteEntries(answer)) this.textures.set(e.id, e);
    $("texture-palette").hidden = !this.textures.size && !upload;
    $("texture-upload").closest("label").hidden = !upload;
    const show = () => {
      $("texture-items").replaceChildren(...[...this.textures.values()].map((e) => {
        const b = document.createElement("button");
        b.type = "button";
        b.dataset.texture = e.id;
        b.title = `${e.name}, a tile ${Math.round(e.widthM * 1000) / 10} × ${Math.round(e.heightM * 1000) / 10} cm`;
        b.setAttribute("aria-label", e.name);
        b.setAttribute("aria-pressed", String(e.id === this.textureId));
        const img = document.createElement("img");
        img.src = this.plan.imageUrl(e.id);
        img.alt = "";
        b.append(img);
        b.addEventListener("click", () => this.pickTexture(e.id));
        return b;
      }));
    };
    this.showTextures = show;
    $("texture-upload").onchange = async (event) => {
      const file = event.target.files?.[0];
      event.target.value = "";
      if (!file || !upload) return;
      try {
        const stored = await upload(file);
        this.textures.set(stored.id, uploadedEntry(stored, file.name));
        this.pickTexture(stored.id);
        this.onStatus(`${file.name} is stored as image ${stored.id}: click a surface in the plan to put it on.`);
      } catch (error) {
        this.onStatus(`${file.name} was not stored: ${error.message}`);
      }
    };
    show();
  }

  pickTexture(id) {
    this.textureId = id;
    this.showTextures?.();
    this.setTool("texture");
  }

  select(pointer) {
    this.selection = pointer;
    this.redraw();
    this.showProperties();
  }

  // The sizes a new wall or opening takes: those of the selected element of its kind (so the panel
  // sets them for the next ones, as it does while a chain of walls is drawn), else `defaults`.
  styleOf(kind, defaults) {
    const el = this.selection ? at({ scene: this.lastScene }, this.selection) : undefined;
    if (!el) return defaults;
    const isWall = /^\/scene\/walls\/\d+$/.test(this.selection);
    if (kind === "wall" && isWall) {
      return { thickness: el.thickness ?? defaults.thickness, height: el.height ?? defaults.height,
        ...(el.base !== undefined ? { base: el.base } : {}), ...(el.color !== undefined ? { color: el.color } : {}) };
    }
    if (kind !== "wall" && this.selection.includes("/openings/") && el.type === kind) {
      const { offset, id, ...rest } = el;
      return rest;
    }
    return defaults;
  }

  bindToolbar() {
    for (const b of document.querySelectorAll("[data-tool]")) b.addEventListener("click", () => this.setTool(b.dataset.tool));
    for (const b of document.querySelectorAll("#catalogue > [data-item]")) {
      b.addEventListener("click", () => {
        this.setItem(b.dataset.item);
        this.setTool("furniture");
      });
    }
    $("eye-height").addEventListener("change", () => this.setEyeHeight());
    const actions = {
      new: () => this.replaceAll(JSON.stringify(newRequest(), null, 2)),
      undo: () => this.step(true),
      redo: () => this.step(false),
      save: () => {
        this.save();
        if (this.onSave) this.onSave();
        else this.onStatus("Saved in this browser; it is restored when the page is opened again.");
      },
      frame: () => this.frameAll(),
    };
    for (const b of document.querySelectorAll("[data-action]")) b.addEventListener("click", () => actions[b.dataset.action]());
    this.actions = actions;
    this.setItem(this.item);
    this.setTool("select");
    this.updateButtons();
  }

  bindPlan() {
    const svg = this.plan.svg;
    svg.addEventListener("pointerdown", (e) => {
      if (e.button !== 0) return;
      svg.focus({ preventScroll: true });
      e.preventDefault();
      // A second press within 400 ms and 4 px is a double-click (the plan is redrawn between the two,
      // so the browser's dblclick, which wants one target under both, is not relied on).
      const p = this.plan.fromClient(e.clientX, e.clientY);
      const last = this.lastPress;
      const double = last && e.timeStamp - last.t < 400 && Math.hypot(e.clientX - last.x, e.clientY - last.y) <= 4;
      this.lastPress = double ? null : { t: e.timeStamp, x: e.clientX, y: e.clientY };
      if (double && tools[this.tool].dblclick) tools[this.tool].dblclick(this, p, e);
      else this.pointerDown(p, e);
    });
    svg.addEventListener("pointermove", (e) => this.pointerMove(this.plan.fromClient(e.clientX, e.clientY), e));
    svg.addEventListener("pointerup", (e) => this.pointerUp(e));
    svg.addEventListener("pointercancel", () => {
      this.drag = null;
      this.redraw();
    });
    // The wheel zooms the plan about the pointer (the scene is not edited).
    svg.addEventListener("wheel", (e) => {
      e.preventDefault();
      const before = this.plan.fromClient(e.clientX, e.clientY);
      this.plan.s = Math.max(2, Math.min(400, this.plan.s * Math.exp(-Math.max(-300, Math.min(300, e.deltaY)) * 0.002)));
      const after = this.plan.toClient(...before);
      this.plan.ox += e.clientX - after.x;
      this.plan.oy += e.clientY - after.y;
      this.redraw();
    }, { passive: false });
    svg.addEventListener("pointerleave", () => {
      this.cursor = null;
      if (tools[this.tool].preview) this.redraw();
    });
  }

  // The properties panel: the selection's fields with the schema's limits; a change is one step.
  showProperties() {
    const request = this.request();
    const element = request && this.selection ? at(request, this.selection) : undefined;
    renderProperties($("properties"), this.selection, element, (field, value) => this.setField(field, value));
  }

  setField(field, value) {
    const problem = fieldProblem(field, value);
    if (problem) {
      this.refuse(problem, null);
      this.showProperties();
      return;
    }
    const pointer = this.selection;
    const current = clone(at(this.request(), pointer));
    let target = current;
    for (const k of field.path.slice(0, -1)) target = target[k] = target[k] ?? clone(field.container ?? {});
    target[field.path[field.path.length - 1]] = value;
    if (pointer.includes("/openings/")) {
      const clash = this.openingProblemAt(pointer, current);
      if (clash) {
        this.refuse(`Not changed: ${clash}.`, null);
        this.showProperties();
        return;
      }
    }
    this.edit((r) => setAt(r.scene, pointer.slice("/scene".length), current));
  }
}

Object.assign(Designer.prototype, toolMethods, commandMethods);
