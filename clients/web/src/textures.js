// The designer's texture palette: the server's texture catalogue (GET /v1/catalogue/textures:
// Sweet Home 3D's, each a read-only stored image) and uploaded images (POST /v1/textures), and which
// surface a click in the plan paints. In: plan points [x, z] (metres, +X right, +Z down) and a scene.
// Out: a texture member ({image: a stored image's 16-hex id, width, height} in metres) and the
// pointer of the element and the member it goes to. Pure functions; no DOM.
import { hitTest, pointInPolygon, wallLength } from "./plan_math.js";
import { onLevel } from "./levels.js";

// The palette: catalogue textures fit to put on a surface (the sky panoramas are left out), in the
// catalogue's order, each {id, name, category, widthM, heightM, url}.
export function paletteEntries(answer) {
  return (answer?.textures || []).filter((t) => t.category !== "Sky").map((t) => ({
    id: t.id,
    name: t.name,
    category: t.category,
    widthM: t.size_cm.width / 100,
    heightM: t.size_cm.height / 100,
    url: t.url,
  }));
}

// An uploaded image's palette entry, from POST /v1/textures's answer: a tile 1 m wide, as tall as
// the image's proportions make it.
export function uploadedEntry(answer, name) {
  const heightM = answer.width > 0 ? Math.round((answer.height / answer.width) * 1000) / 1000 : 1;
  return { id: answer.id, name, category: "Uploaded", widthM: 1, heightM: heightM || 1, url: `/v1/textures/${answer.id}` };
}

// The scene's texture member for a palette entry: the image by id (never a data: URI), one tile's size.
export function textureOf(entry) {
  return { image: entry.id, width: entry.widthM, height: entry.heightM };
}

// Which side of `wall` plan point p is on: "left" faces (dz, −dx) for the direction (dx, dz) from
// start to end (docs/scene-format.md, "Textures").
export function wallSide(wall, p) {
  const dx = wall.end[0] - wall.start[0];
  const dz = wall.end[1] - wall.start[1];
  const along = (p[0] - wall.start[0]) * dz - (p[1] - wall.start[1]) * dx;
  return along >= 0 ? "left" : "right";
}

// The surface a click at p paints, or null: {pointer, member} with the element's JSON Pointer and
// the texture member's name. A wall (or an opening in it) takes the side clicked; then a solid; then
// the floor of the last room holding p; then the floor grid.
export function paintTarget(scene, p, tolM, level = null) {
  const hit = hitTest(scene, p, tolM, level);
  const wall = hit && /^\/scene\/walls\/(\d+)/.exec(hit);
  if (wall) {
    const w = scene.walls[Number(wall[1])];
    return { pointer: `/scene/walls/${wall[1]}`, member: `${wallSide(w, p)}_texture` };
  }
  if (hit && /^\/scene\/solids\/\d+$/.test(hit)) return { pointer: hit, member: "texture" };
  const rooms = scene.rooms || [];
  for (let i = rooms.length - 1; i >= 0; i--) {
    const r = rooms[i];
    if (Array.isArray(r?.points) && r.points.length >= 3 && onLevel(r, level) && pointInPolygon(p, r.points)) {
      return { pointer: `/scene/rooms/${i}`, member: "floor_texture" };
    }
  }
  const f = scene.floor;
  if (f && Array.isArray(f.cells)) {
    const o = f.origin || [0, 0];
    const c = f.cell_size ?? 1;
    if (p[0] >= o[0] && p[1] >= o[1] && p[0] <= o[0] + f.cells[0] * c && p[1] <= o[1] + f.cells[1] * c) {
      return { pointer: "/scene/floor", member: "texture" };
    }
  }
  return null;
}

// The plan's half of `wall` on `side`: the strip from its axis to that face ([x, z] corners), where
// the plan shows that side's texture.
export function wallSideStrip(wall, side) {
  const len = wallLength(wall);
  if (!len) return null;
  const half = (wall.thickness ?? 0.15) / 2;
  const sign = side === "left" ? 1 : -1;
  const n = [(sign * (wall.end[1] - wall.start[1])) / len, (-sign * (wall.end[0] - wall.start[0])) / len];
  const off = (q) => [q[0] + n[0] * half, q[1] + n[1] * half];
  return [wall.start, wall.end, off(wall.end), off(wall.start)];
}

// The stored image an `image` member names, or null (a data: URI, or no texture).
export function storedImageId(texture) {
  const image = texture?.image;
  return typeof image === "string" && /^[0-9a-f]{16}$/.test(image) ? image : null;
}
