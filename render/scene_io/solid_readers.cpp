// JSON -> Solid, one reader per solid type and one row each in the table at the end; the geometry
// of each type is in render/core/solid_<name>.cpp. Every reader checks its keys (a member another
// type has is an unknown key here), types and ranges, and applies the schema's defaults. Invalid
// members and array elements go to b.errors and reading goes on; a rule over several members (a
// simple footprint, planar faces) runs only when those members read cleanly.
#include "render/scene_io/errors.hpp"
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
  ObjectReader r(value, pointer, b.errors,
                 {"type", "id", "level", "color", "material", "center", "base", "rotation_y", "size"});
  read_common(r, s);
  read_footprint(r, s, b);
  s.size = r.vec3("size", b.length);
}

void read_cylinder(const json& value, const std::string& pointer, Solid& s, const Bounds& b) {
  ObjectReader r(value, pointer, b.errors, {"type", "id", "level", "color", "material", "center", "base", "rotation_y",
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
  ObjectReader r(value, pointer, b.errors, {"type", "id", "level", "color", "material", "points", "height", "base"});
  read_common(r, s);
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

std::vector<uint32_t> read_face(const json& value, const std::string& pointer, size_t vertex_count) {
  if (!value.is_array()) throw_invalid(pointer, "must be an array of vertex indices");
  if (value.size() < 3) throw_invalid(pointer, "a face needs at least 3 vertices");
  std::vector<uint32_t> face;
  face.reserve(value.size());
  for (size_t k = 0; k < value.size(); ++k) {
    // The bounds are wide so that an index past the mesh gets the message that names its size.
    long long index = read_integer(value[k], pointer_append(pointer, k), NumberRange{-1e15, 1e15});
    if (index < 0 || static_cast<unsigned long long>(index) >= vertex_count) {
      throw_invalid(pointer_append(pointer, k), "vertex index out of range (the mesh has " +
                                                    std::to_string(vertex_count) + " vertices)");
    }
    face.push_back(static_cast<uint32_t>(index));
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
// Called once the vertices have read cleanly, so their count is the client's.
void read_mesh_normals(const ObjectReader& r, Solid& s) {
  const json& normals = r.array("normals");
  if (normals.empty()) return;
  if (normals.size() != s.vertices.size()) {
    throw_invalid(r.at("normals"), "must hold one normal per vertex (" + std::to_string(s.vertices.size()) +
                                       "), not " + std::to_string(normals.size()));
  }
  s.normals.reserve(normals.size());
  for_each_element(normals, r.at("normals"), r.errors(), [&](const json& value, const std::string& at) {
    Vec3 n = read_vec3(value, at, NumberRange{});
    double length = glm::length(n);
    if (!(length > 0.0) || !std::isfinite(length)) throw_invalid(at, "must be a non-zero vector");
    s.normals.push_back(n / length);
  });
}

// Vertices, faces and normals: each element is checked on its own; the rules over the whole mesh
// (planar faces, one normal per vertex) run only when every vertex and face has read.
void read_mesh_geometry(const ObjectReader& r, Solid& s, const Bounds& b) {
  const json& vertices = r.array("vertices", true);
  const json& faces = r.array("faces", true);
  // Every face is at least one polygon: refuse before spending memory on it.
  if (faces.size() > b.limits.max_polygons) {
    throw_too_large(r.at("faces"), "mesh has " + std::to_string(faces.size()) +
                                       " faces; at most " + std::to_string(b.limits.max_polygons) +
                                       " polygons are allowed");
  }
  const size_t errors_before = b.errors.size();
  s.vertices.reserve(vertices.size());
  for_each_element(vertices, r.at("vertices"), b.errors, [&](const json& v, const std::string& at) {
    s.vertices.push_back(read_vec3(v, at, b.coordinate));
  });
  // A face's indices are checked against the client's vertex count, even when a vertex was refused.
  s.faces.reserve(faces.size());
  for_each_element(faces, r.at("faces"), b.errors, [&](const json& f, const std::string& at) {
    s.faces.push_back(read_face(f, at, vertices.size()));
  });
  if (b.errors.size() != errors_before) return;
  if (auto bad = find_bad_mesh_face(s.vertices, s.faces)) {
    throw_invalid(pointer_append(r.at("faces"), bad->face), bad->problem);
  }
  read_mesh_normals(r, s);
}

void read_mesh(const json& value, const std::string& pointer, Solid& s, const Bounds& b) {
  ObjectReader r(value, pointer, b.errors, {"type", "id", "level", "color", "material", "vertices", "faces", "position",
                                            "scale", "rotation_y", "smooth", "closed", "normals"});
  read_common(r, s);
  b.errors.attempt([&] { read_mesh_geometry(r, s, b); });
  s.position = r.vec3("position", Vec3{0.0}, b.coordinate);
  b.errors.attempt([&] { s.scale = read_scale(r, b); });
  s.rotation_y_deg = r.number("rotation_y", 0.0, NumberRange{});
  s.smooth = r.boolean("smooth", false);
  s.closed = r.boolean("closed", false);
}

constexpr auto readers = std::to_array<SolidReader>({
    {SolidType::box, read_box_or_pyramid},
    {SolidType::cylinder, read_cylinder},
    {SolidType::pyramid, read_box_or_pyramid},
    {SolidType::prism, read_prism},
    {SolidType::mesh, read_mesh},
});

}  // namespace

std::span<const SolidReader> solid_readers() { return readers; }

}  // namespace rr
