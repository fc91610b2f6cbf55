// Parsed JSON -> RenderRequest (docs/scene-format.md): one reader per element, each checking keys,
// types and ranges as it goes and applying the documented defaults, then the semantic rules (openings
// inside their wall, planar mesh faces, simple prism footprints, a usable camera). The first error is
// thrown as an InputError with the JSON Pointer of the offending value.
#include "render/scene_io/scene_json.hpp"

#include "render/scene_io/errors.hpp"
#include "render/scene_io/json_reader.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/core/png.hpp"
#include "render/scene_io/scene_checks.hpp"
#include "render/core/shading.hpp"
#include "render/core/tessellate.hpp"

#include <algorithm>
#include <cfloat>
#include <climits>
#include <cmath>

namespace rr {

using nlohmann::json;
using Kind = InputError::Kind;

namespace {

// Ranges derived from the limits, shared by every reader.
struct Bounds {
  explicit Bounds(const ParseLimits& l)
      : limits(l),
        coordinate{-l.max_abs_coordinate, l.max_abs_coordinate},
        length{0.0, l.max_abs_coordinate, true},
        distance{0.0, l.max_abs_coordinate} {}
  const ParseLimits& limits;
  NumberRange coordinate;  // positions, centres, elevations, bases
  NumberRange length;      // sizes, thickness, heights, radii: > 0
  NumberRange distance;    // offsets and sills: >= 0
};

const NumberRange unit_interval{0.0, 1.0};
const NumberRange intensity_range{0.0, FLT_MAX};  // stored as float

// Documented default colours are written as in the doc, so the two cannot drift apart.
Color hex(const char* text) { return read_color(json(text), ""); }

// The "type" member of an element, before its other keys can be checked (they depend on it).
std::string read_type(const json& value, const std::string& pointer) {
  if (!value.is_object()) throw_invalid(pointer, "must be an object");
  auto it = value.find("type");
  if (it == value.end()) throw_invalid(pointer, "missing required key \"type\"");
  if (!it->is_string()) throw_invalid(pointer_append(pointer, "type"), "must be a string");
  return it->get<std::string>();
}

MaterialParams read_material(const ObjectReader& owner) {
  MaterialParams out;
  const json* value = owner.find("material");
  if (!value) return out;
  ObjectReader r(*value, owner.at("material"), {"specular", "specular_color", "shininess"});
  out.specular = float(r.number("specular", 0.0, unit_interval));
  out.specular_color = r.color("specular_color", out.specular_color);
  out.shininess = float(r.number("shininess", 32.0, NumberRange{1.0, 10000.0}));
  return out;
}

// --- floor -------------------------------------------------------------------------------------------

void read_cells(const ObjectReader& r, Floor& floor, const ParseLimits& limits) {
  const json& cells = r.require("cells");
  std::string pointer = r.at("cells");
  if (!cells.is_array() || cells.size() != 2) throw_invalid(pointer, "must be an array of 2 integers");
  NumberRange count{1.0, double(std::min<long long>(limits.max_floor_cells, INT_MAX))};
  count.kind_above = Kind::too_large;
  long long nx = read_integer(cells[0], pointer_append(pointer, size_t(0)), count);
  long long nz = read_integer(cells[1], pointer_append(pointer, size_t(1)), count);
  if (nx > limits.max_floor_cells / nz) {  // nx * nz without overflow
    throw_too_large(pointer, "floor has " + std::to_string(nx) + " x " + std::to_string(nz) +
                                 " cells; at most " + std::to_string(limits.max_floor_cells) +
                                 " are allowed");
  }
  floor.cells_x = int(nx);
  floor.cells_z = int(nz);
}

Floor read_floor(const json& value, const std::string& pointer, const Bounds& b) {
  ObjectReader r(value, pointer,
                 {"id", "origin", "cells", "cell_size", "elevation", "colors", "material"});
  Floor floor;
  floor.id = r.string("id", "");
  floor.origin = r.vec2("origin", Vec2{0.0, 0.0}, b.coordinate);
  read_cells(r, floor, b.limits);
  floor.cell_size = r.number("cell_size", 1.0, b.length);
  floor.elevation = r.number("elevation", 0.0, b.coordinate);
  if (const json* colors = r.find("colors")) {
    expect_array(*colors, r.at("colors"));
    if (colors->size() < 2) throw_invalid(r.at("colors"), "must hold at least 2 colours");
    for (size_t i = 0; i < colors->size(); ++i) {
      floor.colors.push_back(read_color((*colors)[i], pointer_append(r.at("colors"), i)));
    }
  } else {
    floor.colors = {hex("#d9d4c7"), hex("#8c8579")};
  }
  floor.material = read_material(r);
  return floor;
}

// --- walls and openings ------------------------------------------------------------------------------

// Tolerance for an opening reaching exactly to its wall's end or top (the brief's 1e-9 m).
constexpr double fit_tolerance_m = 1e-9;

void check_opening_fits(const Opening& o, const Wall& wall, const std::string& pointer) {
  double length = glm::length(wall.end - wall.start);
  if (o.offset + o.width > length + fit_tolerance_m) {
    throw_invalid(pointer, "opening extends past the end of its wall (offset + width = " +
                               format_number(o.offset + o.width) + " m > length " +
                               format_number(length) + " m)");
  }
  if (o.sill + o.height > wall.height + fit_tolerance_m) {
    throw_invalid(pointer, "opening extends above its wall (sill + height = " +
                               format_number(o.sill + o.height) + " m > wall height " +
                               format_number(wall.height) + " m)");
  }
}

Opening read_opening(const json& value, const std::string& pointer, const Wall& wall,
                     const Bounds& b) {
  std::string type = read_type(value, pointer);
  Opening o;
  if (type == "door") {
    ObjectReader r(value, pointer, {"type", "id", "offset", "width", "height", "color", "leaf"});
    o.type = OpeningType::door;
    o.id = r.string("id", "");
    o.offset = r.number("offset", b.distance);
    o.width = r.number("width", b.length);
    o.height = r.number("height", 2.0, b.length);
    o.color = r.color("color", hex("#8b5a2b"));
    o.leaf = r.boolean("leaf", true);
  } else if (type == "window") {
    ObjectReader r(value, pointer,
                   {"type", "id", "offset", "width", "height", "sill", "color", "opacity"});
    o.type = OpeningType::window;
    o.id = r.string("id", "");
    o.offset = r.number("offset", b.distance);
    o.width = r.number("width", b.length);
    o.height = r.number("height", 1.2, b.length);
    o.sill = r.number("sill", 0.9, b.distance);
    o.color = r.color("color", hex("#a8c8e8"));
    o.opacity = float(r.number("opacity", 0.35, unit_interval));
    o.leaf = false;  // a window has no leaf
  } else {
    throw_invalid(pointer_append(pointer, "type"), "must be \"door\" or \"window\"");
  }
  check_opening_fits(o, wall, pointer);
  return o;
}

Wall read_wall(const json& value, const std::string& pointer, const Bounds& b) {
  ObjectReader r(value, pointer, {"id", "start", "end", "thickness", "height", "base", "color",
                                  "openings", "material"});
  Wall wall;
  wall.id = r.string("id", "");
  wall.start = r.vec2("start", b.coordinate);
  wall.end = r.vec2("end", b.coordinate);
  // Joins treat end points within 1e-6 m as one point, so a shorter wall has no direction.
  if (glm::length(wall.end - wall.start) <= 1e-6) {
    throw_invalid(r.at("end"), "must be more than 1e-6 m from start");
  }
  wall.thickness = r.number("thickness", 0.15, b.length);
  wall.height = r.number("height", 2.5, b.length);
  wall.base = r.number("base", 0.0, b.coordinate);
  wall.color = r.color("color", hex("#e6e1d6"));
  wall.material = read_material(r);
  const json& openings = r.array("openings");
  for (size_t i = 0; i < openings.size(); ++i) {
    wall.openings.push_back(read_opening(openings[i], pointer_append(r.at("openings"), i), wall, b));
  }
  if (auto overlap = find_overlapping_openings(wall.openings)) {
    throw_invalid(pointer_append(r.at("openings"), overlap->second),
                  "opening overlaps opening " + std::to_string(overlap->first) +
                      " of the same wall along its length");
  }
  return wall;
}

// --- solids ------------------------------------------------------------------------------------------

// Above this many footprint points the O(n^2) simplicity test would cost more than a request should.
constexpr size_t max_prism_points = 4096;

void read_common(const ObjectReader& r, Solid& s) {
  s.id = r.string("id", "");
  s.color = r.color("color", Color{0.7f, 0.7f, 0.7f});  // the schema's default; the doc gives none
  s.material = read_material(r);
}

void read_footprint(const ObjectReader& r, Solid& s, const Bounds& b) {
  s.center = r.vec2("center", b.coordinate);
  s.base = r.number("base", 0.0, b.coordinate);
  s.rotation_y_deg = r.number("rotation_y", 0.0, NumberRange{});
}

void read_box_or_pyramid(const json& value, const std::string& pointer, Solid& s, const Bounds& b) {
  ObjectReader r(value, pointer,
                 {"type", "id", "color", "material", "center", "base", "rotation_y", "size"});
  read_common(r, s);
  read_footprint(r, s, b);
  s.size = r.vec3("size", b.length);
}

void read_cylinder(const json& value, const std::string& pointer, Solid& s, const Bounds& b) {
  ObjectReader r(value, pointer, {"type", "id", "color", "material", "center", "base", "rotation_y",
                                  "radius", "height", "segments", "smooth", "caps"});
  read_common(r, s);
  read_footprint(r, s, b);
  s.radius = r.number("radius", b.length);
  s.height = r.number("height", b.length);
  NumberRange segments{3.0, double(b.limits.max_cylinder_segments)};
  segments.kind_above = Kind::too_large;
  s.segments = int(r.integer("segments", 32, segments));
  s.smooth = r.boolean("smooth", true);
  s.caps = r.boolean("caps", true);
}

void read_prism(const json& value, const std::string& pointer, Solid& s, const Bounds& b) {
  ObjectReader r(value, pointer, {"type", "id", "color", "material", "points", "height", "base"});
  read_common(r, s);
  const json& points = r.array("points", true);
  if (points.size() < 3) throw_invalid(r.at("points"), "must hold at least 3 points");
  if (points.size() > max_prism_points) {
    throw_too_large(r.at("points"), "must hold at most " + std::to_string(max_prism_points) + " points");
  }
  for (size_t i = 0; i < points.size(); ++i) {
    s.points.push_back(read_vec2(points[i], pointer_append(r.at("points"), i), b.coordinate));
  }
  if (std::string problem = simple_polygon_problem(s.points); !problem.empty()) {
    throw_invalid(r.at("points"), "must be a simple polygon: " + problem);
  }
  s.height = r.number("height", b.length);
  s.base = r.number("base", 0.0, b.coordinate);
}

std::vector<uint32_t> read_face(const json& value, const std::string& pointer, size_t vertex_count) {
  if (!value.is_array()) throw_invalid(pointer, "must be an array of vertex indices");
  if (value.size() < 3) throw_invalid(pointer, "a face needs at least 3 vertices");
  std::vector<uint32_t> face;
  face.reserve(value.size());
  for (size_t k = 0; k < value.size(); ++k) {
    const json& index = value[k];
    if (!index.is_number_integer()) throw_invalid(pointer_append(pointer, k), "must be an integer");
    // Text parsing stores non-negative integers as unsigned; JSON built in code may use signed.
    bool negative = !index.is_number_unsigned() && index.get<long long>() < 0;
    if (negative || index.get<uint64_t>() >= vertex_count) {
      throw_invalid(pointer_append(pointer, k), "vertex index out of range (the mesh has " +
                                                    std::to_string(vertex_count) + " vertices)");
    }
    face.push_back(index.get<uint32_t>());
  }
  if (auto repeat = find_repeated_index(face)) {
    throw_invalid(pointer_append(pointer, *repeat), "vertex " + std::to_string(face[*repeat]) +
                                                        " appears twice in this face");
  }
  return face;
}

Vec3 read_scale(const ObjectReader& r, const Bounds& b) {
  const json* value = r.find("scale");
  if (!value) return Vec3{1.0};
  // Positive only: a mirroring scale would turn closed meshes inside out.
  if (value->is_number()) return Vec3{read_number(*value, r.at("scale"), b.length)};
  if (!value->is_array()) throw_invalid(r.at("scale"), "must be a number or an array of 3 numbers");
  return read_vec3(*value, r.at("scale"), b.length);
}

// Optional per-vertex shading normals (e.g. an OBJ's vn): one per vertex, each non-zero; stored unit.
void read_mesh_normals(const ObjectReader& r, Solid& s) {
  const json& normals = r.array("normals");
  if (normals.empty()) return;
  if (normals.size() != s.vertices.size()) {
    throw_invalid(r.at("normals"), "must hold one normal per vertex (" + std::to_string(s.vertices.size()) +
                                       "), not " + std::to_string(normals.size()));
  }
  s.normals.reserve(normals.size());
  for (size_t i = 0; i < normals.size(); ++i) {
    std::string at = pointer_append(r.at("normals"), i);
    Vec3 n = read_vec3(normals[i], at, NumberRange{});
    double length = glm::length(n);
    if (!(length > 0.0) || !std::isfinite(length)) throw_invalid(at, "must be a non-zero vector");
    s.normals.push_back(n / length);
  }
}

void read_mesh(const json& value, const std::string& pointer, Solid& s, const Bounds& b) {
  ObjectReader r(value, pointer, {"type", "id", "color", "material", "vertices", "faces", "position",
                                  "scale", "rotation_y", "smooth", "closed", "normals"});
  read_common(r, s);
  const json& vertices = r.array("vertices", true);
  const json& faces = r.array("faces", true);
  // Every face is at least one polygon: refuse before spending memory on it.
  if (faces.size() > b.limits.max_polygons) {
    throw_too_large(r.at("faces"), "mesh has " + std::to_string(faces.size()) +
                                       " faces; at most " + std::to_string(b.limits.max_polygons) +
                                       " polygons are allowed");
  }
  s.vertices.reserve(vertices.size());
  for (size_t i = 0; i < vertices.size(); ++i) {
    s.vertices.push_back(read_vec3(vertices[i], pointer_append(r.at("vertices"), i), b.coordinate));
  }
  s.faces.reserve(faces.size());
  for (size_t j = 0; j < faces.size(); ++j) {
    s.faces.push_back(read_face(faces[j], pointer_append(r.at("faces"), j), s.vertices.size()));
  }
  if (auto bad = find_bad_mesh_face(s.vertices, s.faces)) {
    throw_invalid(pointer_append(r.at("faces"), bad->face), bad->problem);
  }
  read_mesh_normals(r, s);
  s.position = r.vec3("position", Vec3{0.0}, b.coordinate);
  s.scale = read_scale(r, b);
  s.rotation_y_deg = r.number("rotation_y", 0.0, NumberRange{});
  s.smooth = r.boolean("smooth", false);
  s.closed = r.boolean("closed", false);
}

Solid read_solid(const json& value, const std::string& pointer, const Bounds& b) {
  std::string type = read_type(value, pointer);
  Solid s;
  if (type == "box" || type == "pyramid") {
    s.type = type == "box" ? SolidType::box : SolidType::pyramid;
    read_box_or_pyramid(value, pointer, s, b);
  } else if (type == "cylinder") {
    s.type = SolidType::cylinder;
    read_cylinder(value, pointer, s, b);
  } else if (type == "prism") {
    s.type = SolidType::prism;
    read_prism(value, pointer, s, b);
  } else if (type == "mesh") {
    s.type = SolidType::mesh;
    read_mesh(value, pointer, s, b);
  } else {
    throw_invalid(pointer_append(pointer, "type"),
                  "must be one of \"box\", \"cylinder\", \"pyramid\", \"prism\", \"mesh\"");
  }
  return s;
}

// --- lights and the scene ----------------------------------------------------------------------------

Light read_light(const json& value, const std::string& pointer, const Bounds& b) {
  std::string type = read_type(value, pointer);
  Light light;
  if (type == "directional") {
    ObjectReader r(value, pointer, {"type", "id", "direction", "color", "intensity"});
    light.type = LightType::directional;
    light.id = r.string("id", "");
    Vec3 direction = r.vec3("direction", Vec3{0.0, -1.0, 0.0}, b.coordinate);
    double length = glm::length(direction);  // 0 also when the squares underflow
    if (!(length > 0.0)) throw_invalid(r.at("direction"), "must not be the zero vector");
    light.direction = direction / length;
    light.color = r.color("color", hex("#ffffff"));
    light.intensity = float(r.number("intensity", 1.0, intensity_range));
  } else if (type == "point") {
    ObjectReader r(value, pointer, {"type", "id", "position", "color", "intensity", "attenuation"});
    light.type = LightType::point;
    light.id = r.string("id", "");
    light.position = r.vec3("position", b.coordinate);
    light.color = r.color("color", hex("#ffffff"));
    light.intensity = float(r.number("intensity", 1.0, intensity_range));
    light.attenuation = r.vec3("attenuation", Vec3{1.0, 0.0, 0.0}, NumberRange{0.0, DBL_MAX});
    if (light.attenuation == Vec3{0.0}) throw_invalid(r.at("attenuation"), "must not be all zero");
  } else {
    throw_invalid(pointer_append(pointer, "type"), "must be \"directional\" or \"point\"");
  }
  return light;
}

Ambient read_ambient(const json& value, const std::string& pointer) {
  ObjectReader r(value, pointer, {"color", "intensity"});
  Ambient ambient;
  ambient.color = r.color("color", hex("#ffffff"));
  ambient.intensity = float(r.number("intensity", 0.2, intensity_range));
  return ambient;
}

// Reads r[key] as an array and appends one element per entry.
template <class T>
void read_list(const ObjectReader& r, const char* key, const Bounds& b, std::vector<T>& out,
               T (*read)(const json&, const std::string&, const Bounds&)) {
  const json& items = r.array(key);
  out.reserve(items.size());
  for (size_t i = 0; i < items.size(); ++i) out.push_back(read(items[i], pointer_append(r.at(key), i), b));
}

Scene read_scene(const json& value, const std::string& pointer, const Bounds& b) {
  ObjectReader r(value, pointer,
                 {"version", "background", "ambient", "floor", "walls", "solids", "lights"});
  if (r.find("version") && r.integer("version", 1, NumberRange{}) != 1) {
    throw_invalid(r.at("version"), "must be 1 (the only format version)");
  }
  Scene scene;
  scene.background = r.color("background", hex("#000000"));
  if (const json* ambient = r.find("ambient")) scene.ambient = read_ambient(*ambient, r.at("ambient"));
  if (const json* floor = r.find("floor")) {
    scene.geometry.has_floor = true;
    scene.geometry.floor = read_floor(*floor, r.at("floor"), b);
  }
  read_list(r, "walls", b, scene.geometry.walls, read_wall);
  read_list(r, "solids", b, scene.geometry.solids, read_solid);
  read_list(r, "lights", b, scene.lights, read_light);
  return scene;
}

// --- camera and options ------------------------------------------------------------------------------

void check_view(const ObjectReader& r, const Camera& c) {
  Vec3 view = c.target - c.position;
  double view_length = glm::length(view);
  if (!(view_length > 0.0)) {
    throw_invalid(r.at(r.find("target") ? "target" : "position"), "camera position and target coincide");
  }
  double up_length = glm::length(c.up);
  if (!(up_length > 0.0)) throw_invalid(r.at("up"), "must not be the zero vector");
  // sin of the angle between up and the view direction; below 1e-6 the look-at basis degenerates.
  double sine = glm::length(glm::cross(view / view_length, c.up / up_length));
  if (!(sine > 1e-6)) throw_invalid(r.at("up"), "must not be parallel to the view direction");
}

Camera read_camera(const json& value, const std::string& pointer, const Bounds& b) {
  ObjectReader r(value, pointer, {"position", "target", "up", "fov_y", "near", "far"});
  Camera c;
  c.position = r.vec3("position", c.position, b.coordinate);
  c.target = r.vec3("target", c.target, b.coordinate);
  c.up = r.vec3("up", c.up, b.coordinate);
  c.fov_y_deg = r.number("fov_y", c.fov_y_deg, NumberRange{1.0, 170.0, true, true});
  c.near = r.number("near", c.near, b.length);
  c.far = r.number("far", c.far, NumberRange{c.near, DBL_MAX, true});
  double ratio_limit = b.limits.max_far_over_near;
  if (c.far / c.near > ratio_limit) {
    throw_invalid(r.at("far"), "far / near = " + format_number(c.far / c.near) +
                                   " exceeds " + format_number(ratio_limit) +
                                   " (depth precision would be lost)");
  }
  check_view(r, c);
  return c;
}

template <class Table>
std::string table_names(const Table& table) {
  std::string names;
  for (const auto& row : table) names += (names.empty() ? "" : ", ") + std::string(row.name);
  return names;
}

// One of `names` (index = enumerator), or an error at the member naming them all.
template <class Enum, size_t N>
Enum read_choice(ObjectReader& r, const char* key, Enum fallback, const std::array<std::string_view, N>& names) {
  const json* value = r.find(key);
  if (!value) return fallback;
  for (size_t i = 0; i < N; ++i) {
    if (value->is_string() && value->get_ref<const std::string&>() == names[i]) return Enum(i);
  }
  std::string list;
  for (std::string_view name : names) list += (list.empty() ? "" : ", ") + std::string(name);
  throw_invalid(r.at(key), "must be one of: " + list);
}

constexpr std::array<std::string_view, 4> painter_keys = {"mean", "min", "max", "newell"};

PainterKey read_painter(const json& value, const std::string& pointer) {
  ObjectReader r(value, pointer, {"key"});
  return read_choice(r, "key", PainterKey::mean, painter_keys);
}

constexpr std::array<std::string_view, 2> bsp_traversals = {"front_to_back", "back_to_front"};
constexpr std::array<std::string_view, 2> shadow_fits = {"view", "scene"};

BspOptions read_bsp(const json& value, const std::string& pointer) {
  ObjectReader r(value, pointer, {"w1", "w2", "w3", "epsilon", "max_candidates", "traversal"});
  BspOptions o;
  const NumberRange weight{-1e6, 1e6};
  o.w1 = r.number("w1", o.w1, weight);
  o.w2 = r.number("w2", o.w2, weight);
  o.w3 = r.number("w3", o.w3, weight);
  o.epsilon = r.number("epsilon", o.epsilon, NumberRange{0.0, 1e-2});
  o.max_candidates = int(r.integer("max_candidates", o.max_candidates, NumberRange{1.0, 4096.0}));
  o.traversal = read_choice(r, "traversal", o.traversal, bsp_traversals);
  return o;
}

ShadowOptions read_shadow(const json& value, const std::string& pointer) {
  ObjectReader r(value, pointer, {"size", "pcf", "bias", "slope_bias", "fit"});
  ShadowOptions o;
  NumberRange size{64.0, 4096.0};
  size.kind_above = Kind::too_large;
  o.size = int(r.integer("size", o.size, size));
  o.pcf = int(r.integer("pcf", o.pcf, NumberRange{1.0, 5.0}));
  if (o.pcf % 2 == 0) throw_invalid(r.at("pcf"), "must be 1, 3 or 5");
  o.bias = r.number("bias", o.bias, NumberRange{-100.0, 100.0});
  o.slope_bias = r.number("slope_bias", o.slope_bias, NumberRange{-100.0, 100.0});
  o.fit = read_choice(r, "fit", o.fit, shadow_fits);
  return o;
}

PngCompression read_png(const json& value, const std::string& pointer) {
  ObjectReader r(value, pointer, {"compression"});
  PngCompression mode = PngCompression::fast;
  if (const json* name = r.find("compression")) {
    const PngCompressionInfo* info =
        name->is_string() ? find_png_compression(name->get<std::string>()) : nullptr;
    if (!info) throw_invalid(r.at("compression"), "must be one of: " + table_names(png_compression_table()));
    mode = info->mode;
  }
  return mode;
}

RenderOptions read_options(const json& value, const std::string& pointer, const Bounds& b) {
  ObjectReader r(value, pointer,
                 {"width", "height", "pipeline", "shading", "painter", "bsp", "shadows", "shadow", "png"});
  RenderOptions o;
  NumberRange side{1.0, double(b.limits.max_image_side)};
  side.kind_above = Kind::too_large;
  o.width = int(r.integer("width", o.width, side));
  o.height = int(r.integer("height", o.height, side));
  if (long long pixels = 1LL * o.width * o.height; pixels > b.limits.max_pixels) {
    throw_too_large(r.at("width"), "width * height = " + std::to_string(pixels) +
                                       " pixels; at most " + std::to_string(b.limits.max_pixels) +
                                       " are allowed");
  }
  if (const json* name = r.find("pipeline")) {
    const PipelineInfo* info = name->is_string() ? find_pipeline(name->get<std::string>()) : nullptr;
    if (!info) throw_invalid(r.at("pipeline"), "must be one of: " + table_names(pipeline_table()));
    o.pipeline = info->kind;
  }
  if (const json* name = r.find("shading")) {
    const ShadingInfo* info = name->is_string() ? find_shading(name->get<std::string>()) : nullptr;
    if (!info) throw_invalid(r.at("shading"), "must be one of: " + table_names(shading_table()));
    o.shading = info->mode;
  }
  if (const json* painter = r.find("painter")) o.painter_key = read_painter(*painter, r.at("painter"));
  if (const json* bsp = r.find("bsp")) o.bsp = read_bsp(*bsp, r.at("bsp"));
  o.shadows = r.boolean("shadows", o.shadows);
  if (const json* shadow = r.find("shadow")) o.shadow = read_shadow(*shadow, r.at("shadow"));
  if (const json* png = r.find("png")) o.png_compression = read_png(*png, r.at("png"));
  return o;
}

}  // namespace

RenderRequest request_from_json(const json& request, const ParseLimits& limits) {
  ObjectReader r(request, "", {"scene", "camera", "options"});
  Bounds b(limits);
  RenderRequest out;
  if (const json* scene = r.find("scene")) out.scene = read_scene(*scene, r.at("scene"), b);
  // Checked after validation (the estimate assumes valid geometry) but before anything is built.
  if (size_t estimate = estimate_polygon_count(out.scene.geometry); estimate > limits.max_polygons) {
    throw_too_large("/scene", "scene would have about " + std::to_string(estimate) +
                                  " polygons; at most " + std::to_string(limits.max_polygons) +
                                  " are allowed");
  }
  if (const json* camera = r.find("camera")) out.camera = read_camera(*camera, r.at("camera"), b);
  if (const json* options = r.find("options")) out.options = read_options(*options, r.at("options"), b);
  return out;
}

RenderRequest parse_request(std::string_view text, const ParseLimits& limits) {
  return request_from_json(parse_json_text(text, limits), limits);
}

}  // namespace rr
