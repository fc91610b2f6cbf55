// The room designer: tools that edit the request through the plan (walls, doors, windows, furniture,
// lights, select/move/rotate/delete/duplicate), a properties panel, undo/redo and autosave. In: the
// request editor (its text stays the one source of truth) and pointer/key events. Out: edits made by
// JSON Pointer through the editor, one history step each. The history holds whole request texts;
// a JSON text edit becomes one step once it has rested (or before the next designer action), and
// camera moves are not steps: undo keeps the camera where it is.
import { PlanView } from "./plan_view.js";
import { makeFurniture } from "./catalogue.js";
import { snapWallPoint, snapToGrid, wallEnds, hitTest, projectOnWall, openingAt, openingProblem, moveSolid,
  solidAnchor, distance, roundPoint, sceneBounds, moveWallEnds, wallsProblem } from "./plan_math.js";
import { renderProperties, fieldProblem } from "./properties.js";
import { History } from "./history.js";
import { withDefaults, atEyeHeight, walkStep, frameBounds } from "./camera.js";

const $ = (id) => document.getElementById(id);
const clone = (v) => JSON.parse(JSON.stringify(v));
const storageKey = "roomrender.designer.request";
const textStepDelayMs = 600;
const snapPx = 10;  // wall ends within this many pixels catch the pointer
const eyeHeightM = 1.6;

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

const openingDefaults = {
  door: { type: "door", width: 0.9, height: 2.0 },
  window: { type: "window", width: 1.2, height: 1.2, sill: 0.9 },
};

// The element a pointer names inside the request, or undefined.
function at(request, pointer) {
  let v = request;
  for (const t of pointer.split("/").slice(1)) v = v == null ? undefined : v[t];
  return v;
}

export class Designer {
  constructor(editor, { onEdited, onStatus }) {
    this.editor = editor;
    this.onEdited = onEdited;      // a designer edit was applied: render
    this.onStatus = onStatus;
    this.plan = new PlanView($("plan"));
    this.tool = "select";
    this.item = "table";
    this.selection = null;
    this.chain = [];               // wall tool: points clicked so far
    this.cursor = null;
    this.drag = null;
    this.marks = new Map();
    this.history = new History(editor.text());
    this.applying = false;
    this.parsedText = null;
    this.parsedValue = null;
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

  // The parsed request, kept while the text is the same: the plan redraws on every pointer move, and
  // an imported home's text takes a while to parse. Callers treat it as read-only (edit() copies).
  request() {
    const text = this.editor.text();
    if (text !== this.parsedText) {
      this.parsedText = text;
      this.parsedValue = this.editor.parsed();
    }
    return this.parsedValue;
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
  replaceAll(text, { render = true } = {}) {
    this.flushTextStep();
    const before = this.editor.text();
    this.editor.serverNotes = [];
    this.applyText(text);
    if (before === "") this.history.reset(this.editor.text());
    else this.history.record(before, this.editor.text());
    this.selection = null;
    this.chain = [];
    this.marks = new Map();
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
    try {
      localStorage.setItem(storageKey, this.editor.text());
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
    try {
      this.plan.draw(this.drag?.scene || this.lastScene, {
        selection: this.selection,
        marks: this.marks,
        preview: this.tool === "wall" ? { chain: this.chain, cursor: this.cursor } : null,
        camera: request?.camera,
      });
    } catch (error) {
      // A request that parses but is not a scene yet (typing): the plan keeps what it could draw.
      console.debug("plan:", error);
    }
  }

  fit() {
    this.plan.fit(this.request()?.scene);
    this.redraw();
  }

  // Warnings and errors of the last answer, drawn on the elements they name ({pointer, detail, severity}).
  setMarks(notes) {
    this.marks = new Map();
    for (const n of notes) {
      const m = /^\/scene\/(walls\/\d+(\/openings\/\d+)?|solids\/\d+|lights\/\d+|floor)/.exec(n.pointer || "");
      if (!m) continue;
      const pointer = m[0];
      const old = this.marks.get(pointer);
      this.marks.set(pointer, {
        severity: old?.severity === "error" || n.severity === "error" ? "error" : "warning",
        text: old ? `${old.text}\n${n.detail}` : n.detail,
      });
    }
    this.redraw();
  }

  // ---- tools ---------------------------------------------------------------------------------

  setTool(tool) {
    if (this.tool === "wall" && tool !== "wall") this.chain = [];
    const wasWalk = this.tool === "walk";
    this.tool = tool;
    for (const b of document.querySelectorAll("[data-tool]")) b.setAttribute("aria-pressed", String(b.dataset.tool === tool));
    $("catalogue").classList.toggle("inactive", tool !== "furniture");
    document.body.dataset.tool = tool;
    if (tool === "walk" && !wasWalk) this.startWalk();
    this.redraw();
  }

  setItem(item) {
    this.item = item;
    for (const b of document.querySelectorAll("[data-item]")) b.setAttribute("aria-pressed", String(b.dataset.item === item));
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
    for (const b of document.querySelectorAll("[data-item]")) {
      b.addEventListener("click", () => {
        this.setItem(b.dataset.item);
        this.setTool("furniture");
      });
    }
    const actions = {
      new: () => this.replaceAll(JSON.stringify(newRequest(), null, 2)),
      undo: () => this.step(true),
      redo: () => this.step(false),
      save: () => {
        this.save();
        this.onStatus("Saved in this browser; it is restored when the page is opened again.");
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
      this.pointerDown(this.plan.fromClient(e.clientX, e.clientY), e);
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
      if (this.tool === "wall") this.redraw();
    });
  }

  tolerance() {
    return snapPx / this.plan.s;
  }

  pointerDown(p, e) {
    const scene = this.lastScene;
    if (this.tool === "wall") this.clickWall(p);
    else if (this.tool === "door" || this.tool === "window") this.clickOpening(p, e);
    else if (this.tool === "furniture") this.dropFurniture(p);
    else if (this.tool === "light") this.clickLight(p, e);
    else if (this.tool === "select") {
      // An end of the selected wall: dragging it moves that corner (and the walls meeting there).
      const wall = /^\/scene\/walls\/\d+$/.test(this.selection || "") ? at({ scene }, this.selection) : null;
      const end = wall && [wall.start, wall.end].find((q) => distance(p, q) <= this.tolerance());
      if (end) {
        this.drag = { pointer: "/scene/walls", corner: end, from: p, original: clone(scene.walls), moved: false, scene: null };
        this.plan.svg.setPointerCapture(e.pointerId);
        return;
      }
      const hit = hitTest(scene, p, this.tolerance());
      this.select(hit);
      if (hit && /^\/scene\/walls\/\d+$/.test(hit)) {
        this.drag = { pointer: "/scene/walls", wall: at({ scene }, hit), from: p, original: clone(scene.walls), moved: false, scene: null };
        this.plan.svg.setPointerCapture(e.pointerId);
      } else if (hit && !hit.endsWith("floor")) {
        this.drag = { pointer: hit, from: p, original: clone(at({ scene }, hit)), moved: false, scene: null };
        this.plan.svg.setPointerCapture(e.pointerId);
      }
    }
  }

  pointerMove(p) {
    if (this.tool === "wall") {
      this.cursor = snapWallPoint(p, this.chain[this.chain.length - 1], [...wallEnds(this.lastScene.walls), ...this.chain], this.tolerance());
      this.redraw();
      return;
    }
    if (!this.drag) return;
    const d = [p[0] - this.drag.from[0], p[1] - this.drag.from[1]];
    if (!this.drag.moved && Math.hypot(d[0], d[1]) * this.plan.s < 3) return;
    this.drag.moved = true;
    const scene = clone(this.lastScene);
    const moved = this.drag.corner ? this.movedCorner(this.drag, p)
      : this.drag.wall ? this.movedWall(this.drag, d) : this.movedElement(this.drag.pointer, this.drag.original, d);
    if (!moved) return;
    setAt(scene, this.drag.pointer.slice("/scene".length), moved);
    this.drag.scene = scene;
    this.drag.result = moved;
    this.redraw();
  }

  pointerUp() {
    const drag = this.drag;
    this.drag = null;
    if (!drag || !drag.moved || !drag.result) {
      this.redraw();
      return;
    }
    const problem = drag.pointer.includes("/openings/") ? this.openingProblemAt(drag.pointer, drag.result)
      : drag.pointer === "/scene/walls" ? wallsProblem(drag.result) : null;
    if (problem) {
      this.refuse(problem, null);
      this.redraw();
      return;
    }
    this.edit((r) => setAt(r.scene, drag.pointer.slice("/scene".length), drag.result));
  }

  // The element moved by d metres in plan (snapped to the grid), or null when it cannot move.
  movedElement(pointer, el, d) {
    const snapD = snapToGrid(d, 0.05);
    if (pointer.includes("/openings/")) {
      const wall = at({ scene: this.lastScene }, pointer.replace(/\/openings\/\d+$/, ""));
      const len = distance(wall.start, wall.end);
      const along = (snapD[0] * (wall.end[0] - wall.start[0]) + snapD[1] * (wall.end[1] - wall.start[1])) / len;
      return { ...el, offset: Math.round(Math.max(0, Math.min(len - el.width, el.offset + along)) * 1000) / 1000 };
    }
    if (pointer.startsWith("/scene/solids/")) {
      const a = solidAnchor(el);
      return moveSolid(el, [a[0] + snapD[0], a[1] + snapD[1]]);
    }
    if (pointer.startsWith("/scene/lights/") && el.type === "point") {
      return { ...el, position: [roundPoint([el.position[0] + snapD[0], 0])[0], el.position[1], roundPoint([0, el.position[2] + snapD[1]])[1]] };
    }
    return null;
  }

  // The walls with the dragged wall moved by d (on the grid), the walls meeting its ends following.
  movedWall(drag, d) {
    const snapD = snapToGrid(d, 0.05);
    const shift = (q) => ({ from: q, to: [q[0] + snapD[0], q[1] + snapD[1]] });
    return moveWallEnds(drag.original, [shift(drag.wall.start), shift(drag.wall.end)]);
  }

  // The walls with the dragged corner on the pointer (snapped as the wall tool snaps, from the
  // selected wall's other end).
  movedCorner(drag, p) {
    const wall = at({ scene: { walls: drag.original } }, this.selection);
    const other = distance(wall.start, drag.corner) < 1e-6 ? wall.end : wall.start;
    const ends = wallEnds(drag.original).filter((q) => distance(q, drag.corner) >= 1e-6);
    const to = snapWallPoint(p, other, ends, this.tolerance());
    return moveWallEnds(drag.original, [{ from: drag.corner, to }]);
  }

  clickWall(p) {
    const last = this.chain[this.chain.length - 1];
    const q = snapWallPoint(p, last, [...wallEnds(this.lastScene.walls), ...this.chain], this.tolerance());
    if (!last) {
      this.chain = [q];
      this.cursor = q;
      this.redraw();
      return;
    }
    if (distance(q, last) < 1e-6) return;
    const added = this.edit((r) => {
      r.scene.walls = r.scene.walls || [];
      r.scene.walls.push({ start: last, end: q, ...this.styleOf("wall", { thickness: 0.15, height: 2.5 }) });
      this.selection = `/scene/walls/${r.scene.walls.length - 1}`;
    });
    if (!added) return;
    if (this.chain.length >= 2 && distance(q, this.chain[0]) < 1e-6) this.chain = [];  // closed
    else this.chain.push(q);
    this.redraw();
  }

  clickOpening(p, e) {
    const hit = hitTest({ walls: this.lastScene.walls }, p, this.tolerance());
    const m = hit && /^\/scene\/walls\/(\d+)/.exec(hit);
    if (!m) {
      this.refuse(`a ${this.tool} goes into a wall: click on one`, e);
      return;
    }
    const index = Number(m[1]);
    const wall = this.lastScene.walls[index];
    const opening = openingAt(wall, projectOnWall(wall, p).t, this.styleOf(this.tool, openingDefaults[this.tool]));
    const problem = openingProblem(wall, opening);
    if (problem) {
      this.refuse(`No ${this.tool} here: ${problem}.`, e);
      return;
    }
    this.edit((r) => {
      const w = r.scene.walls[index];
      w.openings = w.openings || [];
      w.openings.push(opening);
      this.selection = `/scene/walls/${index}/openings/${w.openings.length - 1}`;
    });
  }

  openingProblemAt(pointer, opening) {
    const m = /^\/scene\/walls\/(\d+)\/openings\/(\d+)$/.exec(pointer);
    const wall = this.lastScene.walls[Number(m[1])];
    return openingProblem(wall, opening, Number(m[2]));
  }

  // Says in place why an action was refused: a note at the pointer in the plan, and in the status.
  refuse(reason, e) {
    const note = $("plan-refusal");
    note.textContent = reason;
    note.hidden = false;
    const box = $("plan").getBoundingClientRect();
    const wrap = $("plan-wrap").getBoundingClientRect();
    const x = e ? e.clientX - wrap.left : box.width / 2;
    const y = e ? e.clientY - wrap.top : 20;
    note.style.left = `${Math.max(0, Math.min(box.width - 220, x + 10))}px`;
    note.style.top = `${y + 10}px`;
    clearTimeout(this.refusalTimer);
    this.refusalTimer = setTimeout(() => { note.hidden = true; }, 5000);
    this.onStatus(reason);
  }

  nextId(item, solids) {
    const used = new Set(solids.map((s) => s.id));
    let n = 1;
    while (used.has(`${item}-${n}`)) n++;
    return `${item}-${n}`;
  }

  dropFurniture(p) {
    const point = snapToGrid(p, 0.05);
    this.edit((r) => {
      r.scene.solids = r.scene.solids || [];
      r.scene.solids.push(makeFurniture(this.item, point, this.nextId(this.item, r.scene.solids)));
      this.selection = `/scene/solids/${r.scene.solids.length - 1}`;
    });
  }

  // Click: a point light 2.4 m up. Shift+click: the selected (or first) directional light travels
  // toward the clicked point from the plan's centre, 45° downward.
  clickLight(p, e) {
    const point = snapToGrid(p, 0.05);
    if (e.shiftKey) {
      this.edit((r) => {
        const lights = (r.scene.lights = r.scene.lights || []);
        const sel = this.selection && /^\/scene\/lights\/(\d+)$/.exec(this.selection);
        let i = sel && lights[Number(sel[1])]?.type === "directional" ? Number(sel[1]) : lights.findIndex((l) => l.type === "directional");
        if (i < 0) i = lights.push({ type: "directional" }) - 1;
        const b = this.plan.fromClient(...Object.values(this.planCentre()));
        const d = [point[0] - b[0], point[1] - b[1]];
        const len = Math.hypot(d[0], d[1]) || 1;
        lights[i] = { ...lights[i], direction: [d[0] / len, -1, d[1] / len].map((v) => Math.round(v * 1000) / 1000) };
        this.selection = `/scene/lights/${i}`;
      });
      return;
    }
    this.edit((r) => {
      r.scene.lights = r.scene.lights || [];
      r.scene.lights.push({ type: "point", position: [point[0], 2.4, point[1]], intensity: 0.6, attenuation: [1, 0, 0.05] });
      this.selection = `/scene/lights/${r.scene.lights.length - 1}`;
    });
  }

  planCentre() {
    const r = this.plan.svg.getBoundingClientRect();
    return { x: r.left + r.width / 2, y: r.top + r.height / 2 };
  }

  // ---- commands on the selection -------------------------------------------------------------

  deleteSelection() {
    const pointer = this.selection;
    if (!pointer || pointer === "/scene/floor") return;
    const m = /^(.*)\/(\d+)$/.exec(pointer);
    if (!m) return;
    this.selection = null;
    this.edit((r) => {
      const list = at(r, m[1]);
      if (Array.isArray(list)) list.splice(Number(m[2]), 1);
    });
  }

  // Arrow keys in the plan move the selection as a drag by d metres would.
  nudgeSelection(d) {
    const pointer = this.selection;
    const scene = this.lastScene;
    if (/^\/scene\/walls\/\d+$/.test(pointer)) {
      const walls = this.movedWall({ wall: at({ scene }, pointer), original: scene.walls }, d);
      const problem = wallsProblem(walls);
      if (problem) this.refuse(problem, null);
      else this.edit((r) => { r.scene.walls = walls; });
      return;
    }
    const moved = this.movedElement(pointer, at({ scene }, pointer), d);
    if (!moved) return;
    const problem = pointer.includes("/openings/") ? this.openingProblemAt(pointer, moved) : null;
    if (problem) this.refuse(problem, null);
    else this.edit((r) => setAt(r.scene, pointer.slice("/scene".length), moved));
  }

  rotateSelection(deg) {
    const pointer = this.selection;
    if (!pointer || !pointer.startsWith("/scene/solids/")) return;
    this.edit((r) => {
      const s = at(r, pointer);
      if (s.type === "prism") return false;  // its points are already placed
      s.rotation_y = (((s.rotation_y || 0) + deg) % 360 + 360) % 360;
    });
  }

  duplicateSelection() {
    const pointer = this.selection;
    const m = pointer && /^\/scene\/(solids|lights)\/(\d+)$/.exec(pointer);
    if (!m) return;
    this.edit((r) => {
      const list = r.scene[m[1]];
      let copy = clone(list[Number(m[2])]);
      if (m[1] === "solids") {
        copy = moveSolid(copy, solidAnchor(copy).map((v) => v + 0.5));
        const item = (copy.id || "").replace(/-\d+$/, "") || copy.type;
        copy.id = this.nextId(item, list);
      } else if (copy.position) {
        copy.position = [copy.position[0] + 0.5, copy.position[1], copy.position[2] + 0.5];
      }
      list.push(copy);
      this.selection = `/scene/${m[1]}/${list.length - 1}`;
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

  // ---- camera: walk mode and framing (camera.js does the geometry) --------------------------

  moveCamera({ position, target }) {
    this.setCamera([{ pointer: "/camera/position", value: position }, { pointer: "/camera/target", value: target }]);
    this.onEdited();
  }

  startWalk() {
    const request = this.request();
    if (!request) return;
    this.moveCamera(atEyeHeight(request.camera, eyeHeightM));
    $("views").focus({ preventScroll: true });
  }

  walk(forward, right, metres) {
    const request = this.request();
    if (request) this.moveCamera(walkStep(request.camera, forward, right, metres));
  }

  // The plan fitted to the scene, and the camera over all of it.
  frameAll() {
    const request = this.request();
    if (!request) return;
    this.fit();
    const bounds = sceneBounds(request.scene || {}) || [[0, 0], [5, 4]];
    this.moveCamera(frameBounds(bounds, withDefaults(request.camera).fov_y));
  }

  // ---- keyboard ------------------------------------------------------------------------------

  onKey(e) {
    const t = e.target;
    if (t.closest?.(".cm-editor") || ["INPUT", "SELECT", "TEXTAREA"].includes(t.tagName)) return;
    const key = e.key.length === 1 ? e.key.toLowerCase() : e.key;
    const mod = e.ctrlKey || e.metaKey;
    const done = () => {
      e.preventDefault();
      e.stopPropagation();
    };
    if (mod && key === "z") {
      done();
      if (e.shiftKey) this.actions.redo();
      else this.actions.undo();
      return;
    }
    if (mod && key === "y") return done(), this.actions.redo();
    if (mod && key === "d") return done(), this.duplicateSelection();
    if (mod || e.altKey) return;
    if (this.tool === "walk") {
      const moves = { ArrowUp: [1, 0], w: [1, 0], ArrowDown: [-1, 0], s: [-1, 0], ArrowLeft: [0, -1], a: [0, -1],
        ArrowRight: [0, 1], d: [0, 1] };
      if (moves[key]) {
        done();
        this.walk(...moves[key], e.shiftKey ? 1 : 0.25);
        return;
      }
    }
    if (key === "Escape") {
      if (this.tool === "wall" && this.chain.length) {
        this.chain = [];
        this.redraw();
        done();
      } else if (this.tool === "walk") {
        this.setTool("select");
        done();
      } else if (this.selection) {
        this.select(null);
      }
      return;
    }
    const nudges = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, -1], ArrowDown: [0, 1] };
    if (nudges[key] && this.selection && t === this.plan.svg) {
      done();
      this.nudgeSelection(nudges[key].map((v) => v * (e.shiftKey ? 0.5 : 0.05)));
      return;
    }
    if (key === "Delete" || key === "Backspace") return this.selection && (done(), this.deleteSelection());
    if (key === "r" && this.selection) return done(), this.rotateSelection(e.shiftKey ? -15 : 15);
    const tools = { v: "select", w: "wall", d: "door", n: "window", f: "furniture", l: "light", k: "walk" };
    if (tools[key] && !e.target.closest?.("#views")) return done(), this.setTool(tools[key]);
  }
}

// Sets the value at a pointer relative to `root` (its parent must exist).
function setAt(root, pointer, value) {
  const tokens = pointer.split("/").slice(1);
  let parent = root;
  for (const t of tokens.slice(0, -1)) parent = parent[t];
  parent[tokens[tokens.length - 1]] = value;
}
