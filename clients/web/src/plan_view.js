// The plan: the scene seen from above, to scale, drawn into an SVG. In: a request's scene, the
// selection and marks (warnings, errors) by JSON Pointer, and tool previews. Out: SVG elements
// carrying data-pointer. Plan point [x, z] maps to SVG pixel (ox + x·s, oy + z·s): +X right, +Z
// down, s pixels per metre; one SVG pixel is one CSS pixel (no viewBox), so client coordinates are
// the SVG's bounding box plus that.
import { onLevel } from "./levels.js";
import { polygonArea } from "./rooms.js";
import { storedImageId, wallSideStrip } from "./textures.js";
import { wallPolygon, openingPolygon, solidFootprint, solidAnchor, sceneBounds, projectOnWall, wallLength, resizeHandles } from "./plan_math.js";

const NS = "http://www.w3.org/2000/svg";

function el(name, attrs, parent) {
  const e = document.createElementNS(NS, name);
  for (const [k, v] of Object.entries(attrs)) if (v !== undefined && v !== null) e.setAttribute(k, String(v));
  if (parent) parent.append(e);
  return e;
}

function colorText(c, fallback) {
  if (typeof c === "string") return c;
  if (Array.isArray(c)) return `rgb(${c.map((v) => Math.round(Math.max(0, Math.min(1, v)) * 255)).join(",")})`;
  return fallback;
}

// A length of 1, 2 or 5 × 10^k metres between 60 and 150 pixels.
function scaleBarMetres(s) {
  for (let k = -2; k < 6; k++) {
    for (const m of [1, 2, 5]) {
      const len = m * 10 ** k;
      if (len * s >= 60) return len;
    }
  }
  return 1;
}

export class PlanView {
  constructor(svg) {
    this.svg = svg;
    this.s = 50;    // pixels per metre
    this.ox = 40;   // SVG pixel of plan x = 0
    this.oy = 40;   // SVG pixel of plan z = 0
    this.visitor = null;  // {radiusM} in walk mode: the camera is drawn as the visitor
    this.imageUrl = (id) => `/v1/textures/${id}`;  // where a stored image is fetched from
  }

  // The fill of a surface with `texture` (a scene texture member): a pattern of its stored image, one
  // tile its size in metres, from the plan's origin; `fallback` when it names no stored image.
  textureFill(texture, fallback) {
    const id = storedImageId(texture);
    if (!id) return fallback;
    const w = (texture.width ?? 1) * this.s;
    const h = (texture.height ?? 1) * this.s;
    const key = `texture-${id}-${w.toFixed(2)}-${h.toFixed(2)}`.replace(/\./g, "_");
    if (!this.patterns.has(key)) {
      const pattern = el("pattern", { id: key, patternUnits: "userSpaceOnUse", x: this.ox, y: this.oy, width: w, height: h }, this.defs);
      el("image", { href: this.imageUrl(id), width: w, height: h, preserveAspectRatio: "none" }, pattern);
      this.patterns.add(key);
    }
    return `url(#${key})`;
  }

  size() {
    const r = this.svg.getBoundingClientRect();
    return { w: r.width || 400, h: r.height || 400 };
  }

  // Scale and offset so `bounds` (or a 6 × 5 m area for an empty scene) fills the SVG with a margin.
  fit(scene) {
    const b = sceneBounds(scene || {}) || [[-0.5, -0.5], [5.5, 4.5]];
    const { w, h } = this.size();
    const margin = 30;
    const spanX = Math.max(b[1][0] - b[0][0], 1);
    const spanZ = Math.max(b[1][1] - b[0][1], 1);
    this.s = Math.max(2, Math.min(400, Math.min((w - 2 * margin) / spanX, (h - 2 * margin) / spanZ)));
    this.ox = (w - spanX * this.s) / 2 - b[0][0] * this.s;
    this.oy = (h - spanZ * this.s) / 2 - b[0][1] * this.s;
  }

  toSvg([x, z]) {
    return [this.ox + x * this.s, this.oy + z * this.s];
  }

  toClient(x, z) {
    const r = this.svg.getBoundingClientRect();
    const [sx, sy] = this.toSvg([x, z]);
    return { x: r.left + sx, y: r.top + sy };
  }

  fromClient(clientX, clientY) {
    const r = this.svg.getBoundingClientRect();
    return [(clientX - r.left - this.ox) / this.s, (clientY - r.top - this.oy) / this.s];
  }

  points(poly) {
    return poly.map((p) => this.toSvg(p).map((v) => v.toFixed(1)).join(",")).join(" ");
  }

  // Redraws everything. `marks`: Map pointer -> {severity, text}; `clashes`: [{from, to, detail}],
  // pairs of elements a warning names, joined by a line; `preview`: {chain, cursor} of the wall
  // tool; `camera`: the request's camera (eye and direction drawn).
  draw(scene, { selection = null, marks = new Map(), clashes = [], preview = null, camera = null, level = null } = {}) {
    const svg = this.svg;
    svg.replaceChildren();
    this.defs = el("defs", {}, svg);
    this.patterns = new Set();
    const { w, h } = this.size();
    this.drawGrid(w, h);
    const decorate = (node, pointer) => {
      node.dataset.pointer = pointer;
      const mark = marks.get(pointer);
      if (mark) {
        node.classList.add(mark.severity === "error" ? "mark-error" : "mark-warning");
        el("title", {}, node).textContent = mark.text;
      }
      if (pointer === selection) node.classList.add("selected");
      return node;
    };
    if (scene.floor && Array.isArray(scene.floor.cells)) {
      const f = scene.floor;
      const o = f.origin || [0, 0];
      const c = f.cell_size ?? 1;
      const [x, y] = this.toSvg(o);
      const fill = this.textureFill(f.texture, null);  // over the floor's fill in the style sheet
      decorate(el("rect", { x, y, width: f.cells[0] * c * this.s, height: f.cells[1] * c * this.s, class: "floor",
        style: fill ? `fill: ${fill}` : null }, svg), "/scene/floor");
    }
    // Rooms' floor polygons, under everything else and not selectable (the panel edits no room); their
    // names and areas are written over the walls and furniture.
    const labels = [];
    for (const room of scene.rooms || []) {
      if (!Array.isArray(room?.points) || room.points.some((q) => !Array.isArray(q)) || !onLevel(room, level)) continue;
      el("polygon", { points: this.points(room.points), class: "room",
        fill: this.textureFill(room.floor_texture, colorText(room.floor_color, "#d9d4c7")) }, svg);
      if (room.points.length >= 3) labels.push(room);
    }
    (scene.walls || []).forEach((wall, i) => {
      if (!Array.isArray(wall.start) || !Array.isArray(wall.end) || !onLevel(wall, level)) return;
      decorate(el("polygon", { points: this.points(wallPolygon(wall)), class: "wall" }, svg), `/scene/walls/${i}`);
      // A textured side: its half of the wall filled with the image.
      for (const side of ["left", "right"]) {
        const fill = this.textureFill(wall[`${side}_texture`], null);
        const strip = fill && wallSideStrip(wall, side);
        if (strip) el("polygon", { points: this.points(strip), class: "wall-side-texture", fill, "data-side": side }, svg);
      }
      (wall.openings || []).forEach((o, k) => {
        decorate(el("polygon", { points: this.points(openingPolygon(wall, o)), class: `opening ${o.type}` }, svg),
          `/scene/walls/${i}/openings/${k}`);
      });
    });
    const selectedWall = /^\/scene\/walls\/(\d+)$/.exec(selection || "");
    const wall = selectedWall && (scene.walls || [])[Number(selectedWall[1])];
    if (wall && Array.isArray(wall.start) && Array.isArray(wall.end)) {
      for (const q of [wall.start, wall.end]) {
        const [cx, cy] = this.toSvg(q);
        el("circle", { cx, cy, r: 5, class: "handle" }, svg);  // drag to move this corner
      }
    }
    (scene.solids || []).forEach((s, i) => {
      if (!onLevel(s, level)) return;
      let f;
      try {
        f = solidFootprint(s);
      } catch {
        return;  // half-typed in the editor
      }
      // A piece without a colour of its own shows its first part's.
      const fill = this.textureFill(s.texture, colorText(s.color ?? (Array.isArray(s.parts) ? s.parts[0]?.color : undefined), "#b3b3b3"));
      const node = f.circle
        ? el("circle", { cx: this.toSvg(f.circle.center)[0], cy: this.toSvg(f.circle.center)[1], r: f.circle.radius * this.s, class: "solid", fill }, svg)
        : el("polygon", { points: this.points(f.polygon), class: "solid", fill }, svg);
      decorate(node, `/scene/solids/${i}`);
    });
    const selectedSolid = /^\/scene\/solids\/(\d+)$/.exec(selection || "");
    const solid = selectedSolid && (scene.solids || [])[Number(selectedSolid[1])];
    if (solid) {
      resizeHandles(solid).forEach((q, k) => {
        const [cx, cy] = this.toSvg(q);
        el("rect", { x: cx - 4, y: cy - 4, width: 8, height: 8, class: "handle resize", "data-corner": k }, svg);  // drag to resize
      });
    }
    // A pair is joined when both its elements are on the level shown.
    const shown = (pointer) => {
      const m = /^\/scene\/(walls|solids|rooms)\/(\d+)/.exec(pointer);
      return !m || onLevel((scene[m[1]] || [])[Number(m[2])], level);
    };
    for (const c of clashes) if (shown(c.from) && shown(c.to)) this.drawClash(scene, c);
    for (const room of labels) this.drawRoomLabel(room);
    let suns = 0;
    (scene.lights || []).forEach((l, i) => {
      if (l.type === "point" && Array.isArray(l.position)) {
        if (!onLevel(l, level)) return;
        const [cx, cy] = this.toSvg([l.position[0], l.position[2]]);
        decorate(el("circle", { cx, cy, r: 7, class: "light" }, svg), `/scene/lights/${i}`);
      } else if (l.type === "directional") {
        this.drawDirection(l.direction || [0, -1, 0], w, i, suns++, decorate);
      }
    });
    if (camera) this.drawCamera(camera);
    if (preview) this.drawPreview(preview);
    this.drawScaleBar(h);
  }

  // A room's name and floor area at its centroid. The name is its id, less an imported room's
  // "room " prefix and "(/home/room/N)" source suffix.
  drawRoomLabel(room) {
    let a = 0;
    let cx = 0;
    let cz = 0;
    const pts = room.points;
    for (let i = 0, j = pts.length - 1; i < pts.length; j = i++) {
      const cross = pts[j][0] * pts[i][1] - pts[i][0] * pts[j][1];
      a += cross;
      cx += (pts[j][0] + pts[i][0]) * cross;
      cz += (pts[j][1] + pts[i][1]) * cross;
    }
    if (Math.abs(a) < 1e-12) return;
    const [x, y] = this.toSvg([cx / (3 * a), cz / (3 * a)]);
    const text = el("text", { x, y, class: "room-label", "text-anchor": "middle" }, this.svg);
    const name = typeof room.id === "string" ? room.id.replace(/\s*\([^()]*\)$/, "").replace(/^room\s+/, "") : "";
    if (name) el("tspan", { x, dy: "-0.2em" }, text).textContent = name;
    el("tspan", { x, dy: name ? "1.1em" : "0.35em", class: "room-area" }, text).textContent = `${polygonArea(pts).toFixed(2)} m²`;
  }

  drawGrid(w, h) {
    const g = el("g", { class: "grid" }, this.svg);
    const [x0, z0] = [-this.ox / this.s, -this.oy / this.s];
    const [x1, z1] = [(w - this.ox) / this.s, (h - this.oy) / this.s];
    const step = this.s >= 40 ? 0.5 : this.s >= 8 ? 1 : 10;
    for (let x = Math.ceil(x0 / step) * step; x <= x1; x += step) {
      const X = this.ox + x * this.s;
      el("line", { x1: X, y1: 0, x2: X, y2: h, class: Math.abs(x - Math.round(x)) < 1e-9 ? "major" : "" }, g);
    }
    for (let z = Math.ceil(z0 / step) * step; z <= z1; z += step) {
      const Y = this.oy + z * this.s;
      el("line", { x1: 0, y1: Y, x2: w, y2: Y, class: Math.abs(z - Math.round(z)) < 1e-9 ? "major" : "" }, g);
    }
  }

  // A directional light has no place: a dial in the top-right corner (one per such light, side by
  // side) shows where it travels in plan.
  drawDirection(d, w, i, slot, decorate) {
    const g = decorate(el("g", { class: "sun" }, this.svg), `/scene/lights/${i}`);
    const cx = w - 34 - slot * 52;
    const cy = 34;
    el("circle", { cx, cy, r: 22 }, g);
    const len = Math.hypot(d[0], d[2]);
    const [ux, uy] = len > 1e-6 ? [d[0] / len, d[2] / len] : [0, 0];
    el("line", { x1: cx - ux * 16, y1: cy - uy * 16, x2: cx + ux * 16, y2: cy + uy * 16 }, g);
    el("circle", { cx: cx + ux * 16, cy: cy + uy * 16, r: 3 }, g);
    el("title", {}, g).textContent = `directional light ${i}: direction [${d.join(", ")}]`;
  }

  // A line from the solid a warning is about to what it meets: the other solid's anchor, or the
  // nearest point of the wall's centreline.
  drawClash(scene, { from, to, detail }) {
    const at = (pointer, toward) => {
      const m = /^\/scene\/(solids|walls)\/(\d+)$/.exec(pointer);
      const el = m && (scene[m[1]] || [])[Number(m[2])];
      if (!el) return null;
      try {
        if (m[1] === "solids") return solidAnchor(el);
        if (!wallLength(el) || !toward) return null;
        const { t } = projectOnWall(el, toward);
        const len = wallLength(el);
        return [el.start[0] + ((el.end[0] - el.start[0]) * t) / len, el.start[1] + ((el.end[1] - el.start[1]) * t) / len];
      } catch {
        return null;  // half-typed in the editor
      }
    };
    const a = at(from, null);
    const b = a && at(to, a);
    if (!a || !b) return;
    const [x1, y1] = this.toSvg(a);
    const [x2, y2] = this.toSvg(b);
    const g = el("g", { class: "clash" }, this.svg);
    g.dataset.from = from;
    g.dataset.to = to;
    el("line", { x1, y1, x2, y2 }, g);
    el("circle", { cx: x1, cy: y1, r: 3 }, g);
    el("circle", { cx: x2, cy: y2, r: 3 }, g);
    el("title", {}, g).textContent = detail;
  }

  // Moves the camera's mark alone (the rest of the plan stays as drawn): a mark of the same shape is
  // moved by its transform, so a camera step changes one attribute of the plan.
  placeCamera(c) {
    const mark = this.svg.querySelector(":scope > g.camera");
    if (mark && mark.dataset.shape === this.cameraShape(c) && this.poseCamera(mark, c)) return;
    if (mark) mark.remove();
    const bar = this.svg.querySelector(":scope > g.scale-bar");
    this.drawCamera(c);
    if (bar) this.svg.append(bar);
  }

  // What the mark's shape depends on (its pose aside).
  cameraShape(c) {
    return this.visitor ? `visitor ${c.fov_y ?? 60} ${this.s} ${this.visitor.radiusM}` : "camera";
  }

  // Places a mark drawn at the origin looking along +x at the camera's position and heading, and
  // names it in its title. False when the camera has no position or target to place it by.
  poseCamera(g, c) {
    const p = c.position || [0, 1.6, 5];
    const t = c.target || [0, 1, 0];
    if (!Array.isArray(p) || !Array.isArray(t)) return false;
    const [ex, ey] = this.toSvg([p[0], p[2]]);
    const dx = t[0] - p[0];
    const dz = t[2] - p[2];
    const degrees = dx === 0 && dz === 0 ? 0 : (Math.atan2(dz, dx) * 180) / Math.PI;
    g.setAttribute("transform", `translate(${ex.toFixed(2)} ${ey.toFixed(2)}) rotate(${degrees.toFixed(3)})`);
    g.querySelector(":scope > title").textContent = `${this.visitor ? "visitor" : "camera"} at [${p.join(", ")}]` +
      (this.visitor ? `, eye ${p[1]} m` : "");
    return true;
  }

  drawCamera(c) {
    const p = c.position;
    const t = c.target;
    if ((p && !Array.isArray(p)) || (t && !Array.isArray(t))) return;
    let g;
    if (this.visitor) {
      // The visitor: a body of its real size (at least 6 px) and the wedge it sees, 1.5 m long.
      g = el("g", { class: "camera visitor", "data-testid": "visitor" }, this.svg);
      const half = (((c.fov_y ?? 60) / 2) * Math.PI) / 180 * 1.2;
      const r = 1.5 * this.s;
      const wedge = [[0, 0], [r * Math.cos(-half), r * Math.sin(-half)], [r * Math.cos(half), r * Math.sin(half)]];
      el("polygon", { points: wedge.map((q) => q.map((v) => v.toFixed(1)).join(",")).join(" "), class: "view" }, g);
      el("circle", { cx: 0, cy: 0, r: Math.max(6, this.visitor.radiusM * this.s), class: "body" }, g);
      el("line", { x1: 0, y1: 0, x2: Math.max(10, 0.35 * this.s), y2: 0 }, g);
    } else {
      g = el("g", { class: "camera" }, this.svg);
      el("line", { x1: 0, y1: 0, x2: 22, y2: 0 }, g);
      el("circle", { cx: 0, cy: 0, r: 5 }, g);
    }
    el("title", {}, g);
    g.dataset.shape = this.cameraShape(c);
    this.poseCamera(g, c);
  }

  drawPreview({ chain, cursor }) {
    const pts = [...chain, cursor].filter(Boolean);
    if (pts.length >= 2) el("polyline", { points: this.points(pts), class: "preview" }, this.svg);
    if (cursor) {
      const [x, y] = this.toSvg(cursor);
      el("circle", { cx: x, cy: y, r: 4, class: "cursor" }, this.svg);
      if (chain.length) {
        const last = chain[chain.length - 1];
        const len = Math.hypot(cursor[0] - last[0], cursor[1] - last[1]);
        el("text", { x: x + 8, y: y - 8, class: "measure" }, this.svg).textContent = `${len.toFixed(2)} m`;
      }
    }
  }

  drawScaleBar(h) {
    const m = scaleBarMetres(this.s);
    const g = el("g", { class: "scale-bar" }, this.svg);
    const x = 12;
    const y = h - 14;
    el("line", { x1: x, y1: y, x2: x + m * this.s, y2: y }, g);
    el("line", { x1: x, y1: y - 4, x2: x, y2: y + 4 }, g);
    el("line", { x1: x + m * this.s, y1: y - 4, x2: x + m * this.s, y2: y + 4 }, g);
    el("text", { x: x + 2, y: y - 6 }, g).textContent = m >= 1 ? `${m} m` : `${Math.round(m * 100)} cm`;
  }
}
