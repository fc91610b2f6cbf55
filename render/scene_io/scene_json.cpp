// Parsed JSON -> RenderRequest (docs/scene-format.md): one reader per element, each checking keys,
// types and ranges as it goes and applying the documented defaults, then the semantic rules (openings
// inside their wall, planar mesh faces, simple prism footprints, a usable camera). Invalid members and
// elements are gathered in an ErrorList and reading goes on, so the one InputError thrown at the end
// lists every independent problem; a rule that combines members runs only when they read cleanly.
#include "render/scene_io/scene_json.hpp"

#include "render/core/abuffer.hpp"

#include "render/core/camera.hpp"
#include "render/core/raster.hpp"
#include "render/core/sample_pattern.hpp"
#include "render/core/scene_names.hpp"
#include "render/core/solids.hpp"
#include "render/core/tessellate.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/scene_io/errors.hpp"
#include "render/scene_io/json_reader.hpp"
#include "render/scene_io/scene_checks.hpp"
#include "render/scene_io/scene_json_detail.hpp"

#include <algorithm>
#include <cfloat>
#include <climits>
#include <cmath>

namespace rr {

using nlohmann::json;
using Kind = InputError::Kind;

namespace {

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

// The row of `table` that a string value names, or an error at `pointer` listing every name.
template <class Row>
const Row& read_name(const json& value, const std::string& pointer, const NameTable<Row>& table) {
  const Row* row = value.is_string() ? table.find(value.get_ref<const std::string&>()) : nullptr;
  if (!row) throw_invalid(pointer, "must be one of: " + table.choices());
  return *row;
}

// An optional member naming one row of `table`: its value, or `fallback` when the member is absent.
template <class Row, class Value>
Value read_choice(const ObjectReader& r, const char* key, Value fallback, const NameTable<Row>& table) {
  Value out = fallback;
  r.member(key, [&](const json& value, const std::string& pointer) { out = read_name(value, pointer, table).value; });
  return out;
}

}  // namespace

MaterialParams read_material(const ObjectReader& owner) {
  MaterialParams out;
  owner.member("material", [&](const json& value, const std::string& pointer) {
    ObjectReader r(value, pointer, owner.errors(), {"specular", "specular_color", "shininess"});
    out.specular = float(r.number("specular", 0.0, unit_interval));
    out.specular_color = r.color("specular_color", out.specular_color);
    out.shininess = float(r.number("shininess", 32.0, NumberRange{1.0, 10000.0}));
  });
  return out;
}

namespace {

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
    throw_too_large(pointer, "floor has " + std::to_string(nx) + " x " + std::to_string(nz) + " cells; at most " +
                                 std::to_string(limits.max_floor_cells) + " are allowed");
  }
  floor.cells_x = int(nx);
  floor.cells_z = int(nz);
}

Floor read_floor(const json& value, const std::string& pointer, const Bounds& b) {
  ObjectReader r(value, pointer, b.errors,
                 {"id", "origin", "cells", "cell_size", "elevation", "colors", "material", "texture", "level"});
  Floor floor;
  floor.level = read_level_ref(value, pointer, b);
  floor.id = r.string("id", "");
  floor.origin = r.vec2("origin", Vec2{0.0, 0.0}, b.coordinate);
  b.errors.attempt([&] { read_cells(r, floor, b.limits); });
  floor.cell_size = r.number("cell_size", 1.0, b.length);
  floor.elevation = r.number("elevation", 0.0, b.coordinate);
  floor.texture = read_texture(r, "texture", b);
  // A textured floor shows its image as it is unless colours are given to multiply it.
  floor.colors = r.find("texture") ? std::vector<Color>{textured_default_color, textured_default_color}
                                   : std::vector<Color>{hex("#d9d4c7"), hex("#8c8579")};
  r.member("colors", [&](const json& colors, const std::string& at) {
    expect_array(colors, at);
    if (colors.size() < 2) throw_invalid(at, "must hold at least 2 colours");
    floor.colors.clear();
    for_each_element(colors, at, b.errors,
                     [&](const json& c, const std::string& p) { floor.colors.push_back(read_color(c, p)); });
  });
  floor.material = read_material(r);
  return floor;
}

// --- walls and openings ------------------------------------------------------------------------------

// Tolerance for an opening reaching exactly to its wall's end or top (the brief's 1e-9 m).
constexpr double fit_tolerance_m = 1e-9;

// Told in the opening's own terms: a door stands on the wall's base (it has no sill), a window
// starts at its sill.
void check_opening_fits(const Opening& o, const Wall& wall, const std::string& pointer, ErrorList& errors) {
  const bool door = o.type == OpeningType::door;
  const std::string what = door ? "door" : "window";
  double length = glm::length(wall.end - wall.start);
  if (o.offset + o.width > length + fit_tolerance_m) {
    errors.add(pointer, what + " extends past the end of its wall (offset + width = " +
                            format_number(o.offset + o.width) + " m > length " + format_number(length) + " m)");
  }
  if (o.sill + o.height <= wall.height + fit_tolerance_m) return;
  if (door) {
    errors.add(pointer, "door is taller than its wall (height " + format_number(o.height) + " m > wall height " +
                            format_number(wall.height) + " m)");
  } else {
    errors.add(pointer, "window extends above its wall (sill + height = " + format_number(o.sill + o.height) +
                            " m > wall height " + format_number(wall.height) + " m)");
  }
}

// `wall_read`: the wall's own members read cleanly, so the opening can be checked against them.
Opening read_opening(const json& value, const std::string& pointer, const Wall& wall, bool wall_read, const Bounds& b) {
  read_type(value, pointer);
  Opening o;
  o.type = read_name(value.at("type"), pointer_append(pointer, "type"), opening_type_names).value;
  const size_t errors_before = b.errors.size();
  if (o.type == OpeningType::door) {
    ObjectReader r(value, pointer, b.errors, {"type", "id", "offset", "width", "height", "color", "leaf"});
    o.id = r.string("id", "");
    o.offset = r.number("offset", b.distance);
    o.width = r.number("width", b.length);
    o.height = r.number("height", 2.0, b.length);
    o.color = r.color("color", hex("#8b5a2b"));
    o.leaf = r.boolean("leaf", true);
  } else {
    ObjectReader r(value, pointer, b.errors, {"type", "id", "offset", "width", "height", "sill", "color", "opacity"});
    o.id = r.string("id", "");
    o.offset = r.number("offset", b.distance);
    o.width = r.number("width", b.length);
    o.height = r.number("height", 1.2, b.length);
    o.sill = r.number("sill", 0.9, b.distance);
    o.color = r.color("color", hex("#a8c8e8"));
    o.opacity = float(r.number("opacity", 0.35, unit_interval));
    o.leaf = false;  // a window has no leaf
  }
  if (wall_read && b.errors.size() == errors_before) check_opening_fits(o, wall, pointer, b.errors);
  return o;
}

Wall read_wall(const json& value, const std::string& pointer, const Bounds& b) {
  const size_t errors_before = b.errors.size();
  ObjectReader r(value, pointer, b.errors,
                 {"id", "start", "end", "thickness", "height", "base", "color", "left_color", "right_color",
                  "left_texture", "right_texture", "openings", "material", "level"});
  Wall wall;
  wall.level = read_level_ref(value, pointer, b);
  wall.id = r.string("id", "");
  wall.start = r.vec2("start", b.coordinate);
  wall.end = r.vec2("end", b.coordinate);
  // Joins treat end points within 1e-6 m as one point, so a shorter wall has no direction.
  if (b.errors.size() == errors_before && glm::length(wall.end - wall.start) <= 1e-6) {
    b.errors.add(r.at("end"), "must be more than 1e-6 m from start");
  }
  wall.thickness = r.number("thickness", 0.15, b.length);
  wall.height = r.number("height", 2.5, b.length);
  wall.base = r.number("base", 0.0, b.coordinate);
  wall.color = r.color("color", hex("#e6e1d6"));
  wall.material = read_material(r);
  // A side's own colour; a textured side without one is white (the image as it is), not `color`.
  auto read_side_color = [&](const char* key, const char* texture_key) -> std::optional<Color> {
    if (!r.find(key) && !r.find(texture_key)) return std::nullopt;
    return read_surface_color(r, key, texture_key, wall.color);
  };
  wall.left_color = read_side_color("left_color", "left_texture");
  wall.right_color = read_side_color("right_color", "right_texture");
  wall.left_texture = read_texture(r, "left_texture", b);
  wall.right_texture = read_texture(r, "right_texture", b);
  const bool wall_read = b.errors.size() == errors_before;
  r.member("openings", [&](const json& openings, const std::string& at) {
    expect_array(openings, at);
    for_each_element(openings, at, b.errors, [&](const json& o, const std::string& p) {
      wall.openings.push_back(read_opening(o, p, wall, wall_read, b));
    });
  });
  // Indices into wall.openings are indices into the request only when every opening was read.
  if (b.errors.size() != errors_before) return wall;
  if (auto overlap = find_overlapping_openings(wall.openings)) {
    b.errors.add(pointer_append(r.at("openings"), overlap->second),
                 "opening overlaps opening " + std::to_string(overlap->first) + " of the same wall along its length");
  }
  return wall;
}

// --- solids ------------------------------------------------------------------------------------------

Solid read_solid(const json& value, const std::string& pointer, const Bounds& b) {
  read_type(value, pointer);
  Solid s;
  s.type = read_name(value.at("type"), pointer_append(pointer, "type"), solid_table()).value;
  for (const SolidReader& reader : solid_readers()) {
    if (reader.type == s.type) reader.read(value, pointer, s, b);
  }
  s.level = read_level_ref(value, pointer, b);
  return s;
}

// --- lights and the scene ----------------------------------------------------------------------------

Light read_light(const json& value, const std::string& pointer, const Bounds& b) {
  read_type(value, pointer);
  Light light;
  light.type = read_name(value.at("type"), pointer_append(pointer, "type"), light_type_names).value;
  const size_t errors_before = b.errors.size();
  if (light.type == LightType::directional) {
    ObjectReader r(value, pointer, b.errors, {"type", "id", "direction", "color", "intensity"});
    light.id = r.string("id", "");
    Vec3 direction = r.vec3("direction", Vec3{0.0, -1.0, 0.0}, b.coordinate);
    double length = glm::length(direction);  // 0 also when the squares underflow
    if (b.errors.size() == errors_before && !(length > 0.0)) {
      b.errors.add(r.at("direction"), "must not be the zero vector");
    }
    light.direction = length > 0.0 ? direction / length : Vec3{0.0, -1.0, 0.0};
    light.color = r.color("color", hex("#ffffff"));
    light.intensity = float(r.number("intensity", 1.0, intensity_range));
  } else {
    ObjectReader r(value, pointer, b.errors, {"type", "id", "position", "color", "intensity", "attenuation"});
    light.id = r.string("id", "");
    light.position = r.vec3("position", b.coordinate);
    light.color = r.color("color", hex("#ffffff"));
    light.intensity = float(r.number("intensity", 1.0, intensity_range));
    light.attenuation = r.vec3("attenuation", Vec3{1.0, 0.0, 0.0}, NumberRange{0.0, DBL_MAX});
    if (light.attenuation == Vec3{0.0}) b.errors.add(r.at("attenuation"), "must not be all zero");
  }
  return light;
}

Ambient read_ambient(const json& value, const std::string& pointer, ErrorList& errors) {
  ObjectReader r(value, pointer, errors, {"color", "intensity"});
  Ambient ambient;
  ambient.color = r.color("color", hex("#ffffff"));
  ambient.intensity = float(r.number("intensity", 0.2, intensity_range));
  return ambient;
}

// Reads r[key] as an array and appends one element per entry that reads.
template <class T>
void read_list(const ObjectReader& r, const char* key, const Bounds& b, std::vector<T>& out,
               T (*read)(const json&, const std::string&, const Bounds&)) {
  r.member(key, [&](const json& items, const std::string& pointer) {
    expect_array(items, pointer);
    out.reserve(items.size());
    for_each_element(items, pointer, b.errors,
                     [&](const json& item, const std::string& p) { out.push_back(read(item, p, b)); });
  });
}

Scene read_scene(const json& value, const std::string& pointer, const Bounds& scene_bounds) {
  ObjectReader r(value, pointer, scene_bounds.errors,
                 {"version", "background", "ambient", "floor", "walls", "solids", "lights", "rooms", "levels"});
  Scene scene;
  Bounds b = scene_bounds;
  const size_t errors_before = b.errors.size();
  if (r.integer("version", 1, NumberRange{}) != 1 && b.errors.size() == errors_before) {
    b.errors.add(r.at("version"), "must be 1 (the only format version)");
  }
  // Levels first: the other elements name them.
  b.levels = &scene.geometry.levels;
  read_list(r, "levels", b, scene.geometry.levels, read_level);
  check_level_ids(scene.geometry.levels, r.at("levels"), b.errors);
  scene.background = r.color("background", hex("#000000"));
  r.member("ambient", [&](const json& v, const std::string& p) { scene.ambient = read_ambient(v, p, b.errors); });
  r.member("floor", [&](const json& v, const std::string& p) {
    scene.geometry.has_floor = true;
    scene.geometry.floor = read_floor(v, p, b);
  });
  read_list(r, "walls", b, scene.geometry.walls, read_wall);
  read_list(r, "solids", b, scene.geometry.solids, read_solid);
  read_list(r, "rooms", b, scene.geometry.rooms, read_room);
  read_list(r, "lights", b, scene.lights, read_light);
  return scene;
}

// --- camera and options ------------------------------------------------------------------------------

void check_view(const ObjectReader& r, const Camera& c) {
  Vec3 view = c.frame_all ? frame_direction() : c.target - c.position;
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
  ObjectReader r(value, pointer, b.errors, {"position", "target", "up", "fov_y", "near", "far", "frame"});
  const size_t errors_before = b.errors.size();
  Camera c;
  r.member("frame", [&](const json& v, const std::string& p) {
    if (v != "all") throw_invalid(p, "must be \"all\" (frame the whole scene)");
    const char* placed = r.find("position") ? "position" : r.find("target") ? "target" : nullptr;
    if (placed) throw_invalid(p, std::string("frames the scene by choosing position and target; leave out ") + placed);
    c.frame_all = true;
  });
  c.position = r.vec3("position", c.position, b.coordinate);
  c.target = r.vec3("target", c.target, b.coordinate);
  c.up = r.vec3("up", c.up, b.coordinate);
  c.fov_y_deg = r.number("fov_y", c.fov_y_deg, NumberRange{1.0, 170.0, true, true});
  const size_t errors_before_near = b.errors.size();
  c.near = r.number("near", c.near, b.length);
  // far is judged against the near the client gave; when that was refused, only far's own range.
  const double far_above = b.errors.size() == errors_before_near ? c.near : 0.0;
  c.far = r.number("far", c.far, NumberRange{far_above, DBL_MAX, true});
  if (b.errors.size() != errors_before) return c;  // the rules below combine members
  double ratio_limit = b.limits.max_far_over_near;
  if (c.far / c.near > ratio_limit) {
    b.errors.add(r.at("far"), "far / near = " + format_number(c.far / c.near) + " exceeds " +
                                  format_number(ratio_limit) + " (depth precision would be lost)");
  }
  b.errors.attempt([&] { check_view(r, c); });
  return c;
}

PainterKey read_painter(const json& value, const std::string& pointer, ErrorList& errors) {
  ObjectReader r(value, pointer, errors, {"key"});
  return read_choice(r, "key", PainterKey::mean, painter_key_names);
}

BspOptions read_bsp(const json& value, const std::string& pointer, ErrorList& errors) {
  ObjectReader r(value, pointer, errors, {"w1", "w2", "w3", "epsilon", "max_candidates", "traversal"});
  BspOptions o;
  const NumberRange weight{-1e6, 1e6};
  o.w1 = r.number("w1", o.w1, weight);
  o.w2 = r.number("w2", o.w2, weight);
  o.w3 = r.number("w3", o.w3, weight);
  o.epsilon = r.number("epsilon", o.epsilon, NumberRange{0.0, 1e-2});
  o.max_candidates = int(r.integer("max_candidates", o.max_candidates, NumberRange{1.0, 4096.0}));
  o.traversal = read_choice(r, "traversal", o.traversal, bsp_traversal_names);
  return o;
}

ShadowOptions read_shadow(const json& value, const std::string& pointer, ErrorList& errors) {
  ObjectReader r(value, pointer, errors, {"size", "pcf", "bias", "slope_bias", "fit", "method"});
  ShadowOptions o;
  NumberRange size{64.0, 4096.0};
  size.kind_above = Kind::too_large;
  o.size = int(r.integer("size", o.size, size));
  o.pcf = int(r.integer("pcf", o.pcf, NumberRange{1.0, 5.0}));
  if (o.pcf % 2 == 0) errors.add(r.at("pcf"), "must be 1, 3 or 5");
  o.bias = r.number("bias", o.bias, NumberRange{-100.0, 100.0});
  o.slope_bias = r.number("slope_bias", o.slope_bias, NumberRange{-100.0, 100.0});
  o.fit = read_choice(r, "fit", o.fit, shadow_fit_names);
  o.method = read_choice(r, "method", o.method, shadow_method_names);
  return o;
}

PngCompression read_png(const json& value, const std::string& pointer, ErrorList& errors) {
  ObjectReader r(value, pointer, errors, {"compression"});
  return read_choice(r, "compression", PngCompression::fast, png_compression_names);
}

// The ids of the levels a view draws; checked against the scene once both are read.
void read_view_levels(const json& value, const std::string& pointer, ErrorList& errors, RenderOptions& o) {
  expect_array(value, pointer);
  o.levels_given = true;
  for_each_element(value, pointer, errors, [&](const json& id, const std::string& p) {
    if (!id.is_string()) throw_invalid(p, "must be a string: the id of one of the scene's levels");
    o.levels.push_back(id.get<std::string>());
  });
}

RenderOptions read_options(const json& value, const std::string& pointer, const Bounds& b) {
  ObjectReader r(value, pointer, b.errors,
                 {"width", "height", "pipeline", "shading", "painter", "bsp", "shadows", "shadow", "png", "levels",
                  "ceilings", "antialias", "culling", "exposure", "texture_filter"});
  RenderOptions o;
  NumberRange side{1.0, double(std::min(b.limits.max_image_side, max_image_side_for_raster))};
  side.kind_above = Kind::too_large;
  o.width = int(r.integer("width", o.width, side));
  o.height = int(r.integer("height", o.height, side));
  if (long long pixels = 1LL * o.width * o.height; pixels > b.limits.max_pixels) {
    throw_too_large(r.at("width"), "width * height = " + std::to_string(pixels) + " pixels; at most " +
                                       std::to_string(b.limits.max_pixels) + " are allowed");
  }
  r.member("pipeline", [&](const json& name, const std::string& p) {
    o.pipeline = pipeline_id(read_name(name, p, pipeline_table()));
  });
  o.shading = read_choice(r, "shading", o.shading, shading_names);
  r.member("painter", [&](const json& v, const std::string& p) { o.painter_key = read_painter(v, p, b.errors); });
  r.member("bsp", [&](const json& v, const std::string& p) { o.bsp = read_bsp(v, p, b.errors); });
  o.shadows = r.boolean("shadows", o.shadows);
  r.member("shadow", [&](const json& v, const std::string& p) { o.shadow = read_shadow(v, p, b.errors); });
  r.member("png", [&](const json& v, const std::string& p) { o.png_compression = read_png(v, p, b.errors); });
  r.member("levels", [&](const json& v, const std::string& p) { read_view_levels(v, p, b.errors, o); });
  o.ceilings = read_choice(r, "ceilings", o.ceilings, ceiling_mode_names);
  o.antialias = int(r.integer("antialias", o.antialias, NumberRange{1.0, 16.0}));
  if (!is_sample_count(o.antialias)) throw_invalid(r.at("antialias"), "must be 1, 4, 8 or 16");
  o.culling = read_choice(r, "culling", o.culling, culling_mode_names);
  o.texture_filter = read_choice(r, "texture_filter", o.texture_filter, texture_filter_names);
  r.member("exposure", [&](const json& v, const std::string& p) {
    if (v.is_string() && v.get<std::string>() == "auto") {
      o.auto_exposure = true;
    } else if (v.is_number()) {
      o.exposure = read_number(v, p, NumberRange{0.0, max_exposure, true, false});
    } else {
      throw_invalid(p, "must be a number in (0, 64] or \"auto\"");
    }
  });
  // The memory budget: named at the width when one sample per pixel already exceeds it, else at
  // the sub-samples whose A-buffer does.
  const bool plain_over = render_bytes(o.width, o.height, 1) > b.limits.max_render_bytes;
  if (long long bytes = render_bytes(o.width, o.height, o.antialias); bytes > b.limits.max_render_bytes) {
    std::string detail = "a ";
    detail += std::to_string(o.width);
    detail += "x";
    detail += std::to_string(o.height);
    detail += " frame at antialias ";
    detail += std::to_string(o.antialias);
    detail += " needs ";
    detail += std::to_string(bytes);
    detail += " bytes of frame buffers and A-buffer; at most ";
    detail += std::to_string(b.limits.max_render_bytes);
    detail += " are allowed";
    throw_too_large(r.at(plain_over ? "width" : "antialias"), detail);
  }
  return o;
}

RenderRequest read_request(const json& request, const Bounds& b) {
  // A body that is not an object stops here: nothing else in it can be read.
  ObjectReader r(request, "", b.errors, {"scene", "camera", "options"});
  RenderRequest out;
  r.member("scene", [&](const json& v, const std::string& p) { out.scene = read_scene(v, p, b); });
  // Checked after validation (the estimate assumes valid geometry) but before anything is built.
  const size_t estimate = b.errors.size() == 0 ? estimate_polygon_count(out.scene.geometry) : 0;
  if (estimate > b.limits.max_polygons) {
    throw_too_large("/scene", "scene would have about " + std::to_string(estimate) + " polygons; at most " +
                                  std::to_string(b.limits.max_polygons) + " are allowed");
  }
  r.member("camera", [&](const json& v, const std::string& p) { out.camera = read_camera(v, p, b); });
  r.member("options", [&](const json& v, const std::string& p) { out.options = read_options(v, p, b); });
  if (r.find("scene") && b.errors.size() == 0) {
    check_view_levels(out.options, out.scene.geometry.levels, pointer_append(r.at("options"), "levels"), b.errors);
  }
  return out;
}

}  // namespace

RenderRequest request_from_json(const json& request, const ParseLimits& limits) {
  ErrorList errors;
  RenderRequest out;
  TextureImages images;
  Bounds bounds(limits, errors);
  bounds.images = &images;
  try {
    errors.attempt([&] { out = read_request(request, bounds); });
  } catch (const ErrorList::Full&) {
    // The list holds max_listed_errors problems and is marked truncated: answer with what it has.
  }
  errors.throw_if_any();
  return out;
}

RenderRequest parse_request(std::string_view text, const ParseLimits& limits) {
  return request_from_json(parse_json_text(text, limits), limits);
}

}  // namespace rr
