// JSON mesh <-> MeshData (mesh_json.hpp). Each vertex, face, normal and uv is checked on its own and
// the rules over the whole mesh (planar faces of non-zero area, one normal and one uv per vertex) run
// only when every element read, so one pass lists every independent problem.
#include "render/scene_io/mesh_json.hpp"

#include "render/scene_io/errors.hpp"
#include "render/scene_io/scene_checks.hpp"
#include "render/scene_io/scene_json_detail.hpp"

#include <cmath>

namespace rr {

using nlohmann::json;

namespace {

std::vector<uint32_t> read_face(const json& value, const std::string& pointer, size_t vertex_count) {
  if (!value.is_array()) throw_invalid(pointer, "must be an array of vertex indices");
  if (value.size() < 3) throw_invalid(pointer, "a face needs at least 3 vertices");
  std::vector<uint32_t> face;
  face.reserve(value.size());
  for (size_t k = 0; k < value.size(); ++k) {
    // The bounds are wide so that an index past the mesh gets the message that names its size.
    long long index = read_integer(value[k], pointer_append(pointer, k), NumberRange{-1e15, 1e15});
    if (index < 0 || static_cast<unsigned long long>(index) >= vertex_count) {
      throw_invalid(pointer_append(pointer, k),
                    "vertex index out of range (the mesh has " + std::to_string(vertex_count) + " vertices)");
    }
    face.push_back(static_cast<uint32_t>(index));
  }
  if (auto repeat = find_repeated_index(face)) {
    throw_invalid(pointer_append(pointer, *repeat),
                  "vertex " + std::to_string(face[*repeat]) + " appears twice in this face");
  }
  return face;
}

// Optional per-vertex shading normals (e.g. an OBJ's vn): one per vertex, each non-zero; kept unit.
std::vector<Vec3> read_normals(const ObjectReader& r, size_t vertex_count) {
  const json& normals = r.array("normals");
  std::vector<Vec3> out;
  if (normals.empty()) return out;
  if (normals.size() != vertex_count) {
    throw_invalid(r.at("normals"), "must hold one normal per vertex (" + std::to_string(vertex_count) + "), not " +
                                       std::to_string(normals.size()));
  }
  out.reserve(normals.size());
  for_each_element(normals, r.at("normals"), r.errors(), [&](const json& value, const std::string& at) {
    Vec3 n = read_vec3(value, at, NumberRange{});
    double length = glm::length(n);
    if (!(length > 0.0) || !std::isfinite(length)) throw_invalid(at, "must be a non-zero vector");
    // A unit normal is kept bit for bit, so a stored mesh read back keeps its content id.
    out.push_back(std::abs(length - 1.0) <= 1e-12 ? n : n / length);
  });
  return out;
}

// Optional per-vertex texture coordinates (texture.hpp: in tiles, v up): one [u, v] per vertex.
std::vector<glm::dvec2> read_uvs(const ObjectReader& r, size_t vertex_count, const NumberRange& range) {
  const json& uvs = r.array("uvs");
  std::vector<glm::dvec2> out;
  if (uvs.empty()) return out;
  if (uvs.size() != vertex_count) {
    throw_invalid(r.at("uvs"), "must hold one [u, v] per vertex (" + std::to_string(vertex_count) + "), not " +
                                   std::to_string(uvs.size()));
  }
  out.reserve(uvs.size());
  for_each_element(uvs, r.at("uvs"), r.errors(),
                   [&](const json& value, const std::string& at) { out.push_back(read_vec2(value, at, range)); });
  return out;
}

}  // namespace

std::shared_ptr<const MeshData> read_mesh_geometry(const ObjectReader& r, const Bounds& b) {
  const json& vertices = r.array("vertices", true);
  const json& faces = r.array("faces", true);
  // Every face is at least one polygon: refuse before spending memory on it.
  if (faces.size() > b.limits.max_polygons) {
    throw_too_large(r.at("faces"), "mesh has " + std::to_string(faces.size()) + " faces; at most " +
                                       std::to_string(b.limits.max_polygons) + " polygons are allowed");
  }
  if (vertices.size() > b.limits.max_mesh_vertices) {
    throw_too_large(r.at("vertices"), "mesh has " + std::to_string(vertices.size()) + " vertices; at most " +
                                          std::to_string(b.limits.max_mesh_vertices) + " are allowed");
  }
  const size_t errors_before = b.errors.size();
  std::vector<Vec3> points;
  points.reserve(vertices.size());
  for_each_element(vertices, r.at("vertices"), b.errors,
                   [&](const json& v, const std::string& at) { points.push_back(read_vec3(v, at, b.coordinate)); });
  // A face's indices are checked against the client's vertex count, even when a vertex was refused.
  std::vector<std::vector<uint32_t>> indices;
  indices.reserve(faces.size());
  for_each_element(faces, r.at("faces"), b.errors,
                   [&](const json& f, const std::string& at) { indices.push_back(read_face(f, at, vertices.size())); });
  if (b.errors.size() != errors_before) return nullptr;
  if (auto bad = find_bad_mesh_face(points, indices)) {
    throw_invalid(pointer_append(r.at("faces"), bad->face), bad->problem);
  }
  std::vector<Vec3> normals;
  std::vector<glm::dvec2> uvs;
  b.errors.attempt([&] { normals = read_normals(r, points.size()); });
  b.errors.attempt([&] { uvs = read_uvs(r, points.size(), b.coordinate); });
  if (b.errors.size() != errors_before) return nullptr;
  return make_mesh_data(std::move(points), std::move(indices), std::move(normals), std::move(uvs));
}

std::shared_ptr<const MeshData> mesh_from_json(const json& document, const ParseLimits& limits) {
  ErrorList errors;
  std::shared_ptr<const MeshData> mesh;
  try {
    errors.attempt([&] {
      ObjectReader r(document, "", errors, {"vertices", "faces", "normals", "uvs"});
      mesh = read_mesh_geometry(r, Bounds(limits, errors));
    });
  } catch (const ErrorList::Full&) {
    // The list is full and marked truncated: answer with what it has.
  }
  errors.throw_if_any();
  return mesh;
}

json mesh_to_json(const MeshData& mesh) {
  auto points = [](const std::vector<Vec3>& list) {
    json out = json::array();
    for (const Vec3& p : list) out.push_back({p.x, p.y, p.z});
    return out;
  };
  json out = {{"vertices", points(mesh.vertices)}, {"faces", mesh.faces}};
  if (!mesh.normals.empty()) out["normals"] = points(mesh.normals);
  if (!mesh.uvs.empty()) {
    json& uvs = out["uvs"] = json::array();
    for (const glm::dvec2& uv : mesh.uvs) uvs.push_back({uv.x, uv.y});
  }
  return out;
}

}  // namespace rr
