// Commands of the designer on its selection (delete, nudge, rotate, mirror, duplicate), the camera in walk
// mode and framing (camera.js does the geometry), and the keyboard. In: the selection's JSON Pointer
// and key events outside the editor and the form fields. Out: designer steps, or camera edits that
// are no steps. Mixed into Designer.prototype (designer.js), so `this` is the designer.
import { moveSolid, solidAnchor, sceneBounds, wallsProblem } from "./plan_math.js";
import { withDefaults, atEyeHeight, walkStep, frameBounds, roundVec } from "./camera.js";
import { at, setAt, clone } from "./designer_util.js";
import { tools } from "./designer_tools.js";

const $ = (id) => document.getElementById(id);
const eyeHeightM = 1.6;

export const commandMethods = {
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
  },

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
  },

  rotateSelection(deg) {
    const pointer = this.selection;
    if (!pointer || !pointer.startsWith("/scene/solids/")) return;
    this.edit((r) => {
      const s = at(r, pointer);
      if (s.type === "prism") return false;  // its points are already placed
      s.rotation_y = (((s.rotation_y || 0) + deg) % 360 + 360) % 360;
    });
  },

  // A piece of furniture mirrored across its width axis (its `mirrored` turned over), one step.
  mirrorSelection() {
    const pointer = this.selection;
    if (!pointer || !/^\/scene\/solids\/\d+$/.test(pointer)) return;
    this.edit((r) => {
      const s = at(r, pointer);
      if (s.type !== "piece") return false;
      if (s.mirrored) delete s.mirrored;
      else s.mirrored = true;
    });
  },

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
  },

  // ---- camera: walk mode and framing (camera.js does the geometry) --------------------------

  moveCamera({ position, target }) {
    this.setCamera([{ pointer: "/camera/position", value: position }, { pointer: "/camera/target", value: target }]);
    this.onEdited();
  },

  startWalk() {
    const request = this.request();
    if (!request) return;
    this.moveCamera(atEyeHeight(request.camera, eyeHeightM));
    $("views").focus({ preventScroll: true });
  },

  walk(forward, right, metres) {
    const request = this.request();
    if (request) this.moveCamera(walkStep(request.camera, forward, right, metres));
  },

  // The walk tool's keys: arrows and WASD step 0.25 m (Shift: 1 m), Escape goes back to Select. True
  // when the key was one of them.
  walkKey(key, e) {
    const moves = { ArrowUp: [1, 0], w: [1, 0], ArrowDown: [-1, 0], s: [-1, 0], ArrowLeft: [0, -1], a: [0, -1],
      ArrowRight: [0, 1], d: [0, 1] };
    if (moves[key]) {
      this.walk(...moves[key], e.shiftKey ? 1 : 0.25);
      return true;
    }
    if (key !== "Escape") return false;
    this.setTool("select");
    return true;
  },

  // The plan fitted to the scene, and the camera over all of it: the frame the server chooses for
  // "camera": {"frame": "all"} (so the page and API users get the same view), or, from a server
  // without framing, one over the plan's bounds.
  async frameAll() {
    const request = this.request();
    if (!request) return;
    this.fit();
    const framed = await this.frameCamera(request).catch(() => null);
    if (framed) {
      this.moveCamera({ position: roundVec(framed.position), target: roundVec(framed.target) });
      return;
    }
    const bounds = sceneBounds(request.scene || {}) || [[0, 0], [5, 4]];
    this.moveCamera(frameBounds(bounds, withDefaults(request.camera).fov_y));
  },

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
    if (tools[this.tool].key?.(this, key, e)) return done();
    if (key === "Escape") {
      if (this.selection) this.select(null);
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
    if (key === "m" && this.selection) return done(), this.mirrorSelection();
    const tool = Object.keys(tools).find((name) => tools[name].shortcut === key);
    if (tool && !e.target.closest?.("#views")) return done(), this.setTool(tool);
  },
};
