// The corpus of requests the schema test sends: a compact base request touching every element type,
// and named mutations of it. Each case says what both judges must say:
//   valid     the schema accepts and the server renders (200);
//   invalid   the schema rejects and the server refuses (400, 413 or 422);
//   semantic  the schema accepts but the server refuses with 422: rules a JSON Schema cannot state
//             (geometry and relations between fields; scene.schema.json's description lists them);
//   limit     the schema accepts but the server refuses with 413: bounds on work that combine
//             fields (floor cells nx * nz, polygons after tessellation), documented in docs/api.md.
// Every example request in examples/ is added as a valid case by run.mjs.
import { readFileSync } from "node:fs";

const requestOptions = JSON.parse(readFileSync(new URL("../../schemas/request.schema.json", import.meta.url), "utf8"))
  .$defs.options.properties;

export const base = {
  scene: {
    version: 1,
    background: "#202830",
    ambient: { color: [1, 1, 1], intensity: 0.25 },
    floor: { origin: [-3, -3], cells: [6, 6], cell_size: 1, colors: ["#d9d4c7", "#8c8579"], material: { specular: 0.1 } },
    walls: [
      {
        id: "north", start: [-3, -3], end: [3, -3], thickness: 0.15, height: 2.5,
        openings: [
          { type: "door", offset: 0.5, width: 0.9, height: 2.0, leaf: true },
          { type: "window", offset: 2.5, width: 1.2, height: 1.0, sill: 1.0, opacity: 0.4 },
        ],
      },
      { start: [3, -3], end: [3, 3], color: [0.9, 0.9, 0.85] },
    ],
    solids: [
      { type: "box", id: "table", center: [0, 0], size: [1.2, 0.75, 0.8], rotation_y: 15 },
      { type: "cylinder", center: [1.5, 1], radius: 0.3, height: 1.0, segments: 12, smooth: false, caps: true },
      { type: "pyramid", center: [-1.5, 1], size: [0.6, 0.8, 0.6] },
      { type: "prism", points: [[-2, -2], [-1.5, -2], [-1.5, -1.5]], height: 0.5 },
      {
        type: "mesh", vertices: [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
        faces: [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], position: [-0.5, 1, 1.5], scale: 0.4, closed: true,
      },
      {
        type: "piece", id: "chest", center: [2, -2], base: 0, size: [0.6, 0.5, 0.4], rotation_y: 30,
        parts: [
          { name: "body", vertices: [[-0.5, -0.5, -0.5], [0.5, -0.5, -0.5], [0, 0.5, -0.5], [0, -0.5, 0.5]],
            faces: [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], color: "#8b5a2b" },
          { name: "lid", vertices: [[0, 0, 0], [1, 0, 0], [0, 0, 1]], faces: [[0, 2, 1]],
            transform: [[0.5, 0, 0, -0.25], [0, 1, 0, 0.5], [0, 0, 0.5, -0.25]], material: { specular: 0.3 } },
        ],
      },
    ],
    lights: [
      { type: "directional", direction: [-0.3, -1, -0.2], intensity: 0.8 },
      { type: "point", position: [0, 2.2, 0], attenuation: [1, 0.1, 0.02] },
    ],
  },
  camera: { position: [4, 3, 5], target: [0, 0.5, 0], up: [0, 1, 0], fov_y: 60, near: 0.1, far: 100 },
  options: { width: 48, height: 36, pipeline: "zbuffer", shading: "flat", shadows: false },
};

// Sets `value` at a JSON Pointer-like path ("scene/walls/0/height"); undefined deletes the member.
function set(object, path, value) {
  const keys = path.split("/");
  let node = object;
  for (const key of keys.slice(0, -1)) node = node[key];
  const last = keys[keys.length - 1];
  if (value === undefined) delete node[last];
  else node[last] = value;
}

const cases = [];
function add(kind, name, ...edits) {
  const request = structuredClone(base);
  for (const [path, value] of edits) set(request, path, value);
  cases.push({ kind, name, request });
}
const valid = (name, ...edits) => add("valid", name, ...edits);
const invalid = (name, ...edits) => add("invalid", name, ...edits);
const semantic = (name, ...edits) => add("semantic", name, ...edits);
const limit = (name, ...edits) => add("limit", name, ...edits);

valid("base");
cases.push({ kind: "valid", name: "empty request", request: {} });
valid("no options", ["options", undefined]);
valid("integer written as 48.0", ["options/width", 48.0]);
valid("width at its limit", ["options/width", 4096], ["options/height", 1]);
valid("fov_y just inside", ["camera/fov_y", 169.5]);
valid("hex and array colours", ["scene/background", [0, 0, 0]], ["scene/walls/1/color", "#ABCDEF"]);
valid("open doorway", ["scene/walls/0/openings/0/leaf", false]);
valid("cylinder with 3 segments", ["scene/solids/1/segments", 3]);
valid("mesh with per-axis scale", ["scene/solids/4/scale", [0.5, 1, 2]]);
valid("no floor", ["scene/floor", undefined]);
valid("mirrored piece", ["scene/solids/5/mirrored", true]);
valid("piece part without a transform", ["scene/solids/5/parts/1/transform", undefined]);
valid("shadows with tuning", ["options/shadows", true], ["options/shadow", { size: 256, pcf: 3, bias: 0.5 }]);
valid("painter key", ["options/painter", { key: "newell" }]);
// Every pipeline and shading mode the schema lists (tests/unit/test_schema_tables.cpp holds that list
// to the C++ tables), so a new row is exercised here without an edit.
for (const pipeline of requestOptions.pipeline.enum) valid(`pipeline ${pipeline}`, ["options/pipeline", pipeline]);
for (const shading of requestOptions.shading.enum) valid(`shading ${shading}`, ["options/shading", shading]);
valid("bsp weights", ["options/bsp", { w1: 2, w2: 8, w3: 0, epsilon: 0.001, max_candidates: 8 }]);
valid("exposure 2", ["options/exposure", 2]);
valid("exposure at its limit", ["options/exposure", 64]);
valid("exposure auto", ["options/exposure", "auto"]);
// Textures: a real 1 x 1 PNG, and a PNG header alone claiming 100,000 x 100,000 pixels (refused from
// the header, 413 at its image member).
const pngUri = "data:image/png;base64,iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAIAAACQd1PeAAAADElEQVR4nGP438AAAAQBAYDFKhhdAAAAAElFTkSuQmCC";
function crc32(bytes) {
  let c = 0xffffffff;
  for (const b of bytes) {
    c ^= b;
    for (let k = 0; k < 8; ++k) c = (c >>> 1) ^ (0xedb88320 & -(c & 1));
  }
  return (c ^ 0xffffffff) >>> 0;
}
function hugePngUri() {
  const be32 = (v) => [(v >>> 24) & 255, (v >>> 16) & 255, (v >>> 8) & 255, v & 255];
  const chunk = [...Buffer.from("IHDR"), ...be32(100000), ...be32(100000), 8, 2, 0, 0, 0];
  const bytes = [0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a, ...be32(13), ...chunk, ...be32(crc32(chunk))];
  return "data:image/png;base64," + Buffer.from(bytes).toString("base64");
}
valid("textures on every kind of surface",
  ["scene/floor/texture", { image: pngUri, width: 0.5, height: 0.5, x_offset: 0.25, angle: 45 }],
  ["scene/walls/0/left_texture", { image: pngUri }], ["scene/walls/0/right_color", "#ff0000"],
  ["scene/solids/0/texture", { image: pngUri, width: 2 }],
  ["scene/solids/4/texture", { image: pngUri }], ["scene/solids/4/uvs", [[0, 0], [1, 0], [0, 1], [1, 1]]]);
for (const filter of requestOptions.texture_filter.enum) valid(`texture_filter ${filter}`, ["options/texture_filter", filter]);
invalid("texture without an image", ["scene/solids/0/texture", { width: 1 }]);
invalid("texture image a URL", ["scene/solids/0/texture", { image: "https://example.com/a.png" }]);
invalid("texture width 0", ["scene/solids/0/texture", { image: pngUri, width: 0 }]);
invalid("unknown texture key", ["scene/solids/0/texture", { image: pngUri, scale: 2 }]);
invalid("texture_filter cubic", ["options/texture_filter", "cubic"]);
semantic("texture image not an image", ["scene/solids/0/texture", { image: "data:image/png;base64,aGVsbG8=" }]);
semantic("texture image a stored id", ["scene/solids/0/texture", { image: "0123456789abcdef" }]);
limit("texture header 100000 x 100000", ["scene/solids/0/texture", { image: hugePngUri() }]);
valid("material on a solid", ["scene/solids/0/material", { specular: 0.5, specular_color: "#ffffff", shininess: 64 }]);

invalid("unknown top-level key", ["extra", 1]);
invalid("unknown camera key", ["camera/zoom", 2]);
invalid("unknown option", ["options/antialias", true]);
invalid("unknown scene key", ["scene/sky", "#000000"]);
invalid("unknown wall key", ["scene/walls/0/colour", "#ffffff"]);
invalid("unknown solid key", ["scene/solids/0/radius", 1]);
invalid("door with a sill", ["scene/walls/0/openings/0/sill", 0.5]);
invalid("prism with a centre", ["scene/solids/3/center", [0, 0]]);
invalid("width 0", ["options/width", 0]);
invalid("width 4097", ["options/width", 4097]);
invalid("width not an integer", ["options/width", 16.5]);
invalid("width as a string", ["options/width", "640"]);
invalid("negative height", ["options/height", -1]);
invalid("fov_y 1", ["camera/fov_y", 1]);
invalid("fov_y 170", ["camera/fov_y", 170]);
invalid("fov_y a string", ["camera/fov_y", "60"]);
invalid("near 0", ["camera/near", 0]);
invalid("far 0", ["camera/far", 0]);
invalid("unknown pipeline", ["options/pipeline", "raytrace"]);
invalid("unknown shading", ["options/shading", "toon"]);
invalid("unknown painter key", ["options/painter", { key: "median" }]);
invalid("pcf 2", ["options/shadow", { pcf: 2 }]);
invalid("shadow map too small", ["options/shadow", { size: 32 }]);
invalid("shadow map too large", ["options/shadow", { size: 8192 }]);
invalid("bsp epsilon too large", ["options/bsp", { epsilon: 0.1 }]);
invalid("bsp max_candidates 0", ["options/bsp", { max_candidates: 0 }]);
invalid("exposure 0", ["options/exposure", 0]);
invalid("negative exposure", ["options/exposure", -1]);
invalid("exposure above 64", ["options/exposure", 64.5]);
invalid("exposure as another word", ["options/exposure", "bright"]);
invalid("exposure as a numeric string", ["options/exposure", "2"]);
invalid("shadows as a string", ["options/shadows", "yes"]);
invalid("short hex colour", ["scene/background", "#12345"]);
invalid("named colour", ["scene/background", "red"]);
invalid("colour component above 1", ["scene/background", [1, 2, 0]]);
invalid("colour with 2 components", ["scene/background", [0.5, 0.5]]);
invalid("vec3 with 2 items", ["camera/position", [1, 2]]);
invalid("vec3 with a string", ["camera/position", [1, "2", 3]]);
invalid("floor without cells", ["scene/floor/cells", undefined]);
invalid("floor with 0 cells", ["scene/floor/cells", [0, 1]]);
invalid("floor cell size 0", ["scene/floor/cell_size", 0]);
invalid("floor with one colour", ["scene/floor/colors", ["#ffffff"]]);
invalid("wall without start", ["scene/walls/0/start", undefined]);
invalid("wall thickness 0", ["scene/walls/0/thickness", 0]);
invalid("negative wall height", ["scene/walls/1/height", -1]);
invalid("unknown opening type", ["scene/walls/0/openings/0/type", "arch"]);
invalid("negative opening offset", ["scene/walls/0/openings/0/offset", -1]);
invalid("window opacity 1.5", ["scene/walls/0/openings/1/opacity", 1.5]);
invalid("unknown solid type", ["scene/solids/0/type", "sphere"]);
invalid("box without size", ["scene/solids/0/size", undefined]);
invalid("box with zero height", ["scene/solids/0/size", [1, 0, 1]]);
invalid("cylinder with 2 segments", ["scene/solids/1/segments", 2]);
invalid("cylinder with 1025 segments", ["scene/solids/1/segments", 1025]);
invalid("prism with 2 points", ["scene/solids/3/points", [[0, 0], [1, 0]]]);
invalid("mesh without faces", ["scene/solids/4/faces", undefined]);
invalid("mesh face of 2 vertices", ["scene/solids/4/faces/0", [0, 1]]);
invalid("negative mesh index", ["scene/solids/4/faces/0", [0, -1, 2]]);
invalid("repeated mesh index", ["scene/solids/4/faces/0", [0, 2, 2]]);
invalid("mesh with both ref and vertices", ["scene/solids/4/ref", "0123456789abcdef"]);
invalid("piece without parts", ["scene/solids/5/parts", undefined]);
invalid("piece with no part", ["scene/solids/5/parts", []]);
invalid("piece without size", ["scene/solids/5/size", undefined]);
invalid("piece part with both ref and vertices", ["scene/solids/5/parts/0/ref", "0123456789abcdef"]);
invalid("piece part transform of 2 rows", ["scene/solids/5/parts/1/transform", [[1, 0, 0, 0], [0, 1, 0, 0]]]);
invalid("piece part transform row of 3", ["scene/solids/5/parts/1/transform/0", [1, 0, 0]]);
invalid("unknown piece part key", ["scene/solids/5/parts/0/scale", 2]);
invalid("piece with a position", ["scene/solids/5/position", [0, 0, 0]]);
invalid("point light attenuation all zero", ["scene/lights/1/attenuation", [0, 0, 0]]);
invalid("unknown light type", ["scene/lights/0/type", "spot"]);
invalid("point light without position", ["scene/lights/1/position", undefined]);
invalid("negative intensity", ["scene/lights/0/intensity", -1]);
invalid("zero light direction", ["scene/lights/0/direction", [0, 0, 0]]);
invalid("zero up vector", ["camera/up", [0, 0, 0]]);
invalid("scene version 2", ["scene/version", 2]);
invalid("scene is an array", ["scene", []]);
invalid("camera is a string", ["camera", "abc"]);
invalid("options is null", ["options", null]);
invalid("negative ambient", ["scene/ambient/intensity", -0.1]);
invalid("specular above 1", ["scene/solids/0/material", { specular: 1.5 }]);

semantic("wall start equals end", ["scene/walls/1/end", [3, -3]]);
semantic("opening past the wall's end", ["scene/walls/0/openings/1/offset", 5.5]);
semantic("overlapping openings", ["scene/walls/0/openings/1/offset", 1.0]);
semantic("window above its wall", ["scene/walls/0/openings/1/sill", 2.0]);
semantic("mesh index out of range", ["scene/solids/4/faces/0", [0, 2, 9]]);
semantic("mesh ref naming no stored mesh", ["scene/solids/4", { type: "mesh", ref: "0123456789abcdef" }]);
semantic("piece part transform not invertible", ["scene/solids/5/parts/1/transform", [[1, 0, 0, 0], [0, 0, 0, 0], [0, 0, 1, 0]]]);
semantic("piece part ref naming no stored mesh", ["scene/solids/5/parts/0", { ref: "0123456789abcdef" }]);
semantic("self-intersecting prism", ["scene/solids/3/points", [[0, 0], [1, 1], [1, 0], [0, 1]]]);
semantic("far not beyond near", ["camera/near", 5], ["camera/far", 4]);
semantic("far / near above 1e7", ["camera/near", 0.00001], ["camera/far", 1000]);
semantic("camera target at its position", ["camera/target", [4, 3, 5]]);
semantic("up parallel to the view", ["camera/position", [0, 5, 0]], ["camera/target", [0, 0, 0]]);
semantic("coordinate beyond 1e7 m", ["scene/solids/0/center", [20000000, 0]]);
semantic("non-planar mesh face", ["scene/solids/4/vertices/3", [0, 0, 1]],
         ["scene/solids/4/faces", [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3], [0, 1, 2, 3]]]);

limit("floor with more than 1e6 cells", ["scene/floor/cells", [2000, 2000]]);
limit("more than 2e6 polygons after tessellation",
      ["scene/solids", Array.from({ length: 2000 }, (_, i) => ({ type: "cylinder", center: [i, 0], radius: 0.4, height: 1, segments: 1024 }))]);

export { cases };
