// JSON -> Solid, one reader per solid type and one row each in the table at the end; the geometry
// of each type is in render/core/solid_<name>.cpp. Every reader checks its keys (a member another
// type has is an unknown key here), types and ranges, and applies the schema's defaults (mesh
// geometry: mesh_json.cpp). Invalid members and array elements go to b.errors and reading goes on;
// a rule over several members (a simple footprint, planar faces) runs only when those members read
// cleanly.
#include "render/scene_io/errors.hpp"
#include "render/scene_io/mesh_json.hpp"
#include "render/scene_io/scene_checks.hpp"
#include "render/scene_io/scene_json_detail.hpp"

#include <array>
#include <cmath>

namespace rr {

using nlohmann::json;
using Kind = InputError::Kind;

namespace {

// Above this many footprint points the O(n^2) simplicity test would cost more than a request should.
constexpr size_t max_prism_points = 4096;

void read_common(const ObjectReader& r, Solid& s, const Bounds& b) {
  s.id = r.string("id", "");
  s.color = read_surface_color(r, "color", "texture", Color{0.7f, 0.7f, 0.7f});  // the schema's default
  s.material = read_material(r);
  s.texture = read_texture(r, "texture", b);
}

void read_footprint(const ObjectReader& r, Solid& s, const Bounds& b) {
  s.center = r.vec2("center", b.coordinate);
  s.base = r.number("base", 0.0, b.coordinate);
  s.rotation_y_deg = r.number("rotation_y", 0.0, NumberRange{});
}

void read_box_or_pyramid(const json& value, const std::string& pointer, Solid& s, const Bounds& b) {
  ObjectReader r(value, pointer, b.errors,
                 {"type", "id", "level", "color", "material", "texture", "center", "base", "rotation_y", "size"});
  read_common(r, s, b);
  read_footprint(r, s, b);
  s.size = r.vec3("size", b.length);
}

void read_cylinder(const json& value, const std::string& pointer, Solid& s, const Bounds& b) {
  ObjectReader r(value, pointer, b.errors,
                 {"type", "id", "level", "color", "material", "texture", "center", "base", "rotation_y", "radius",
                  "height", "segments", "smooth", "caps"});
  read_common(r, s, b);
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
  ObjectReader r(value, pointer, b.errors,
                 {"type", "id", "level", "color", "material", "texture", "points", "height", "base"});
  read_common(r, s, b);
  const size_t errors_before = b.errors.size();
  b.errors.attempt([&] {
    const json& points = r.array("points", true);
    if (points.size() < 3) throw_invalid(r.at("points"), "must hold at least 3 points");
    if (points.size() > max_prism_points) {
      throw_too_large(r.at("points"), "must hold at most " + std::to_string(max_prism_points) + " points");
    }
    for_each_element(points, r.at("points"), b.errors, [&](const json& point, const std::string& p) {
      s.points.push_back(read_vec2(point, p, b.coordinate));
    });
  });
  if (b.errors.size() == errors_before) {
    if (std::string problem = simple_polygon_problem(s.points); !problem.empty()) {
      b.errors.add(r.at("points"), "must be a simple polygon: " + problem);
    }
  }
  s.height = r.number("height", b.length);
  s.base = r.number("base", 0.0, b.coordinate);
}

Vec3 read_scale(const ObjectReader& r, const Bounds& b) {
  const json* value = r.find("scale");
  if (!value) return Vec3{1.0};
  // Positive only: a mirroring scale would turn closed meshes inside out.
  if (value->is_number()) return Vec3{read_number(*value, r.at("scale"), b.length)};
  if (!value->is_array()) throw_invalid(r.at("scale"), "must be a number or an array of 3 numbers");
  return read_vec3(*value, r.at("scale"), b.length);
}

// "ref": a stored mesh, found through the limits' resolver. It replaces the geometry members.
void read_ref(const ObjectReader& r, std::shared_ptr<const MeshData>& mesh, std::string& mesh_ref, const Bounds& b) {
  const json& ref = r.require("ref");
  if (!ref.is_string()) throw_invalid(r.at("ref"), "must be the id of a stored mesh (a string)");
  for (const char* key : {"vertices", "faces", "normals", "uvs"}) {
    if (r.find(key)) throw_invalid(r.at(key), "a mesh placed by \"ref\" takes its geometry from the stored mesh");
  }
  mesh_ref = ref.get<std::string>();
  if (b.limits.resolve_mesh) mesh = b.limits.resolve_mesh(mesh_ref);
  if (!mesh) throw_invalid(r.at("ref"), "there is no stored mesh \"" + quote_input(mesh_ref) + "\"");
}

void read_mesh(const json& value, const std::string& pointer, Solid& s, const Bounds& b) {
  ObjectReader r(value, pointer, b.errors,
                 {"type", "id", "level", "color", "material", "texture", "vertices", "faces", "position", "scale",
                  "rotation_y", "smooth", "closed", "normals", "uvs", "ref"});
  read_common(r, s, b);
  b.errors.attempt([&] {
    if (r.find("ref")) {
      read_ref(r, s.mesh, s.mesh_ref, b);
    } else {
      s.mesh = read_mesh_geometry(r, b);
    }
  });
  s.position = r.vec3("position", Vec3{0.0}, b.coordinate);
  b.errors.attempt([&] { s.scale = read_scale(r, b); });
  s.rotation_y_deg = r.number("rotation_y", 0.0, NumberRange{});
  s.smooth = r.boolean("smooth", false);
  s.closed = r.boolean("closed", false);
}

// Parts of one piece: a bound on bookkeeping (their faces count against max_polygons as any mesh's).
constexpr size_t max_piece_parts = 4096;

// "transform": [[a, b, c, tx], [d, e, f, ty], [g, h, i, tz]], rows mapping (x, y, z, 1) into the
// piece's unit box; it must be invertible, since normals go through its inverse transpose.
void read_part_transform(const json& value, const std::string& pointer, PiecePart& part, const Bounds& b) {
  const json& rows = expect_array(value, pointer);
  if (rows.size() != 3) throw_invalid(pointer, "must hold 3 rows of 4 numbers");
  for (size_t row = 0; row < 3; ++row) {
    const std::string at = pointer_append(pointer, row);
    const json& cells = expect_array(rows[row], at);
    if (cells.size() != 4) throw_invalid(at, "must hold 4 numbers");
    for (int col = 0; col < 3; ++col) {
      part.linear[col][int(row)] = read_number(cells[size_t(col)], pointer_append(at, size_t(col)), b.coordinate);
    }
    part.offset[int(row)] = read_number(cells[3], pointer_append(at, 3), b.coordinate);
  }
  const double det = glm::determinant(part.linear);
  if (!(std::abs(det) > 1e-12)) {
    throw_invalid(pointer, "must be invertible: its 3x3 part has determinant " + format_number(det));
  }
  part.transformed = true;
}

PiecePart read_part(const json& value, const std::string& pointer, const Solid& piece, const Bounds& b) {
  ObjectReader r(value, pointer, b.errors,
                 {"name", "ref", "vertices", "faces", "normals", "uvs", "color", "material", "texture", "transform"});
  PiecePart part;
  part.name = r.string("name", "");
  // A part takes the piece's colour, material and texture unless it has its own; a part with a texture
  // of its own and no colour is white.
  part.color = read_surface_color(r, "color", "texture", piece.color);
  part.material = r.find("material") ? read_material(r) : piece.material;
  part.texture = r.find("texture") ? read_texture(r, "texture", b) : piece.texture;
  b.errors.attempt([&] {
    if (r.find("ref")) {
      read_ref(r, part.mesh, part.mesh_ref, b);
    } else {
      part.mesh = read_mesh_geometry(r, b);
    }
  });
  r.member("transform", [&](const json& t, const std::string& at) { read_part_transform(t, at, part, b); });
  return part;
}

void read_piece(const json& value, const std::string& pointer, Solid& s, const Bounds& b) {
  ObjectReader r(value, pointer, b.errors,
                 {"type", "id", "level", "color", "material", "texture", "center", "base", "rotation_y", "size",
                  "mirrored", "parts"});
  read_common(r, s, b);
  read_footprint(r, s, b);
  s.size = r.vec3("size", b.length);
  s.mirrored = r.boolean("mirrored", false);
  b.errors.attempt([&] {
    const json& parts = r.array("parts", true);
    if (parts.empty()) throw_invalid(r.at("parts"), "must hold at least one part");
    if (parts.size() > max_piece_parts) {
      throw_too_large(r.at("parts"), "must hold at most " + std::to_string(max_piece_parts) + " parts");
    }
    for_each_element(parts, r.at("parts"), b.errors,
                     [&](const json& part, const std::string& at) { s.parts.push_back(read_part(part, at, s, b)); });
  });
}

constexpr auto readers = std::to_array<SolidReader>({
    {SolidType::box, read_box_or_pyramid},
    {SolidType::cylinder, read_cylinder},
    {SolidType::pyramid, read_box_or_pyramid},
    {SolidType::prism, read_prism},
    {SolidType::mesh, read_mesh},
    {SolidType::piece, read_piece},
});

}  // namespace

std::span<const SolidReader> solid_readers() { return readers; }

}  // namespace rr
