// The plan's pointer tools of the designer: select/drag (elements, walls, wall corners), wall
// chains, doors and windows, furniture and lights, and the table of tools that says what each does.
// In: plan points in metres (+X right, +Z down) and the pointer events they came from. Out: designer
// steps through Designer.edit(), or a refusal said in place. Mixed into Designer.prototype
// (designer.js), so `this` is the designer.
import { makeFurniture } from "./catalogue.js";
import { snapWallPoint, snapToGrid, wallEnds, hitTest, projectOnWall, openingAt, openingProblem, moveSolid,
  solidAnchor, distance, roundPoint, moveWallEnds, wallsProblem, resizeHandles, resizeSolid } from "./plan_math.js";
import { at, setAt, clone } from "./designer_util.js";
import { roomAt } from "./rooms.js";
import { onLevel } from "./levels.js";
import { paintTarget, textureOf } from "./textures.js";

const $ = (id) => document.getElementById(id);
const snapPx = 10;  // wall ends within this many pixels catch the pointer

const openingDefaults = {
  door: { type: "door", width: 0.9, height: 2.0 },
  window: { type: "window", width: 1.2, height: 1.2, sill: 0.9 },
};

// The tools, one row each, every entry optional and given the designer `d`: down(d, p, e), move(d, p)
// and up(d) for the pointer in the plan; key(d, key, e) for a key outside the editor (true when the
// tool took it); dblclick(d, p, e) for a double-click in the plan; preview(d), what the plan draws for the tool; enter(d) and leave(d) when it is
// chosen and left; shortcut, the key that chooses it. A tool without move or up does what Select
// does: it carries on a drag that Select began (a shortcut may change the tool while the pointer is down).
export const tools = {
  select: { shortcut: "v", down: (d, p, e) => d.selectDown(p, e), move: (d, p, e) => d.dragMove(p, e), up: (d) => d.dragEnd() },
  wall: {
    shortcut: "w",
    down: (d, p) => d.clickWall(p),
    move: (d, p) => d.moveWallCursor(p),
    key: (d, key) => key === "Escape" && d.endChain(),
    preview: (d) => ({ chain: d.chain, cursor: d.cursor }),
    leave: (d) => { d.chain = []; },
  },
  room: {
    shortcut: "o",
    down: (d, p) => d.clickRoom(p),
    dblclick: (d, p, e) => d.fillRoom(p, e),
    move: (d, p) => d.moveWallCursor(p),
    key: (d, key) => key === "Escape" && d.endChain(),
    preview: (d) => ({ chain: d.chain, cursor: d.cursor }),
    leave: (d) => { d.chain = []; },
  },
  door: { shortcut: "d", down: (d, p, e) => d.clickOpening(p, e) },
  window: { shortcut: "n", down: (d, p, e) => d.clickOpening(p, e) },
  furniture: { shortcut: "f", down: (d, p) => d.dropFurniture(p) },
  texture: { shortcut: "t", down: (d, p, e) => d.paintAt(p, e) },
  light: { shortcut: "l", down: (d, p, e) => d.clickLight(p, e) },
  walk: {
    shortcut: "k",
    key: (d, key, e) => d.walkKey(key, e),
    enter: (d) => d.startWalk(),
    down: (d, p, e) => d.visitorDown(p, e),
    move: (d, p) => d.visitorMove(p),
    up: (d) => d.visitorUp(),
  },
};

export const toolMethods = {
  tolerance() {
    return snapPx / this.plan.s;
  },

  pointerDown(p, e) {
    tools[this.tool].down?.(this, p, e);
  },

  pointerMove(p, e) {
    (tools[this.tool].move ?? tools.select.move)(this, p, e);
  },

  pointerUp() {
    (tools[this.tool].up ?? tools.select.up)(this);
  },

  // Select: a click selects what is under it and picks it up to drag (an end of the selected wall
  // drags that corner and the walls meeting there; a corner handle of the selected solid resizes it).
  selectDown(p, e) {
    const scene = this.lastScene;
    const solid = /^\/scene\/solids\/\d+$/.test(this.selection || "") ? at({ scene }, this.selection) : null;
    const corner = solid ? resizeHandles(solid).findIndex((q) => distance(p, q) <= this.tolerance()) : -1;
    if (corner >= 0) {
      this.drag = { pointer: this.selection, resize: corner, from: p, original: clone(solid), moved: false, scene: null };
      this.plan.svg.setPointerCapture(e.pointerId);
      return;
    }
    const wall = /^\/scene\/walls\/\d+$/.test(this.selection || "") ? at({ scene }, this.selection) : null;
    const end = wall && [wall.start, wall.end].find((q) => distance(p, q) <= this.tolerance());
    if (end) {
      this.drag = { pointer: "/scene/walls", corner: end, from: p, original: clone(scene.walls), moved: false, scene: null };
      this.plan.svg.setPointerCapture(e.pointerId);
      return;
    }
    const hit = hitTest(scene, p, this.tolerance(), this.level);
    this.select(hit);
    if (hit && /^\/scene\/walls\/\d+$/.test(hit)) {
      this.drag = { pointer: "/scene/walls", wall: at({ scene }, hit), from: p, original: clone(scene.walls), moved: false, scene: null };
      this.plan.svg.setPointerCapture(e.pointerId);
    } else if (hit && !hit.endsWith("floor")) {
      this.drag = { pointer: hit, from: p, original: clone(at({ scene }, hit)), moved: false, scene: null };
      this.plan.svg.setPointerCapture(e.pointerId);
    }
  },

  // Shift held while a corner handle is dragged keeps the solid's proportions.
  dragMove(p, e) {
    if (!this.drag) return;
    const d = [p[0] - this.drag.from[0], p[1] - this.drag.from[1]];
    if (!this.drag.moved && Math.hypot(d[0], d[1]) * this.plan.s < 3) return;
    this.drag.moved = true;
    const scene = clone(this.lastScene);
    const moved = this.drag.resize !== undefined ? resizeSolid(this.drag.original, this.drag.resize, p, Boolean(e?.shiftKey))
      : this.drag.corner ? this.movedCorner(this.drag, p)
      : this.drag.wall ? this.movedWall(this.drag, d) : this.movedElement(this.drag.pointer, this.drag.original, d);
    if (!moved) return;
    const changed = JSON.stringify(moved) !== JSON.stringify(this.drag.result);
    setAt(scene, this.drag.pointer.slice("/scene".length), moved);
    this.drag.scene = scene;
    this.drag.result = moved;
    this.redraw();
    // The image follows the drag at reduced size (5 cm steps: only when the element moved).
    if (changed) this.onDragPreview(scene);
  },

  dragEnd() {
    const drag = this.drag;
    this.drag = null;
    this.onDragPreview(null);
    if (!drag || !drag.moved || !drag.result) {
      this.redraw();
      return;
    }
    const problem = drag.pointer.includes("/openings/") ? this.openingProblemAt(drag.pointer, drag.result)
      : drag.pointer === "/scene/walls" ? wallsProblem(drag.result) : null;
    if (problem) {
      this.refuse(problem, null);
      this.redraw();
      this.onEdited();  // the image showed the drag: back to the scene as it is
      return;
    }
    this.edit((r) => setAt(r.scene, drag.pointer.slice("/scene".length), drag.result));
  },

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
  },

  // The walls with the dragged wall moved by d (on the grid), the walls meeting its ends following.
  movedWall(drag, d) {
    const snapD = snapToGrid(d, 0.05);
    const shift = (q) => ({ from: q, to: [q[0] + snapD[0], q[1] + snapD[1]] });
    return moveWallEnds(drag.original, [shift(drag.wall.start), shift(drag.wall.end)]);
  },

  // The walls with the dragged corner on the pointer (snapped as the wall tool snaps, from the
  // selected wall's other end).
  movedCorner(drag, p) {
    const wall = at({ scene: { walls: drag.original } }, this.selection);
    const other = distance(wall.start, drag.corner) < 1e-6 ? wall.end : wall.start;
    const ends = wallEnds(drag.original).filter((q) => distance(q, drag.corner) >= 1e-6);
    const to = snapWallPoint(p, other, ends, this.tolerance());
    return moveWallEnds(drag.original, [{ from: drag.corner, to }]);
  },

  moveWallCursor(p) {
    this.cursor = snapWallPoint(p, this.chain[this.chain.length - 1], [...wallEnds(this.lastScene.walls), ...this.chain], this.tolerance());
    this.redraw();
  },

  // Escape in a chain of walls ends it; false when no chain was being drawn.
  endChain() {
    if (!this.chain.length) return false;
    this.chain = [];
    this.redraw();
    return true;
  },

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
      const on = this.levelMembers();
      const wall = { start: last, end: q, ...this.styleOf("wall", { thickness: 0.15, height: 2.5 }) };
      r.scene.walls.push(on ? { ...wall, level: on.level, base: wall.base ?? on.elevation } : wall);
      this.selection = `/scene/walls/${r.scene.walls.length - 1}`;
    });
    if (!added) return;
    if (this.chain.length >= 2 && distance(q, this.chain[0]) < 1e-6) this.chain = [];  // closed
    else this.chain.push(q);
    this.redraw();
  },

  // Room: clicks put corners (snapped as walls are), a click on the first corner closes the room; a
  // double-click inside closed walls fills the room they make, drawn to their inner faces.
  clickRoom(p) {
    const last = this.chain[this.chain.length - 1];
    const q = snapWallPoint(p, last, [...wallEnds(this.lastScene.walls), ...this.chain], this.tolerance());
    if (this.chain.length >= 3 && distance(q, this.chain[0]) < 1e-6) {
      const points = this.chain;
      this.chain = [];
      this.addRoom(points);
      return;
    }
    if (!last || distance(q, last) >= 1e-6) this.chain.push(q);
    this.cursor = q;
    this.redraw();
  },

  fillRoom(p, e) {
    this.chain = [];
    const walls = (this.lastScene.walls || []).filter((w) => onLevel(w, this.level));
    const points = roomAt(walls, p);
    if (!points) {
      this.refuse("No closed walls around this point: draw the room's corners with clicks, or close its walls first.", e);
      this.redraw();
      return;
    }
    this.addRoom(points);
  },

  addRoom(points) {
    this.edit((r) => {
      r.scene.rooms = r.scene.rooms || [];
      const on = this.levelMembers();
      const room = { id: this.nextId("room", r.scene.rooms), points: points.map((q) => [q[0], q[1]]) };
      r.scene.rooms.push(on ? { ...room, level: on.level } : room);
      this.selection = null;
    });
  },

  clickOpening(p, e) {
    const hit = hitTest({ walls: this.lastScene.walls }, p, this.tolerance(), this.level);
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
  },

  openingProblemAt(pointer, opening) {
    const m = /^\/scene\/walls\/(\d+)\/openings\/(\d+)$/.exec(pointer);
    const wall = this.lastScene.walls[Number(m[1])];
    return openingProblem(wall, opening, Number(m[2]));
  },

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
  },

  nextId(item, elements) {
    const used = new Set(elements.map((s) => s.id));
    let n = 1;
    while (used.has(`${item}-${n}`)) n++;
    return `${item}-${n}`;
  },

  dropFurniture(p) {
    const point = snapToGrid(p, 0.05);
    this.edit((r) => {
      r.scene.solids = r.scene.solids || [];
      const made = makeFurniture(this.item, point, this.nextId(this.item, r.scene.solids), this.catalogue);
      if (!made) return false;
      const on = this.levelMembers();
      const solid = on ? { ...made, level: on.level, base: on.elevation + (made.base ?? 0) } : made;
      r.scene.solids.push(solid);
      this.selection = `/scene/solids/${r.scene.solids.length - 1}`;
    });
  },

  // Texture: a click puts the palette's texture on the surface under it (textures.js, paintTarget):
  // a wall's side, a solid, a room's floor or the floor grid; the texture names the stored image by id.
  paintAt(p, e) {
    const entry = this.textures.get(this.textureId);
    if (!entry) {
      this.refuse("Pick a texture in the palette first.", e);
      return;
    }
    const target = paintTarget(this.lastScene, p, this.tolerance(), this.level);
    if (!target) {
      this.refuse("No surface here: click a wall side, a room, the floor or a solid.", e);
      return;
    }
    this.edit((r) => {
      at(r, target.pointer)[target.member] = textureOf(entry);
    });
  },

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
      const y = 2.4 + (this.levelMembers()?.elevation ?? 0);
      r.scene.lights.push({ type: "point", position: [point[0], y, point[1]], intensity: 0.6, attenuation: [1, 0, 0.05] });
      this.selection = `/scene/lights/${r.scene.lights.length - 1}`;
    });
  },

  planCentre() {
    const r = this.plan.svg.getBoundingClientRect();
    return { x: r.left + r.width / 2, y: r.top + r.height / 2 };
  },
};
