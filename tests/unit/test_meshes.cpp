// Shared meshes: the canonical MeshData and its content id, the JSON and OBJ mesh readers with their
// pointers and lines, "ref" solids resolved through the limits, the scene id over referenced meshes,
// and instanced tessellation (one plan per mesh, each placement equal to a transformed copy).
#include "render/core/scene_id.hpp"
#include "render/core/tessellate.hpp"
#include "render/import/obj_mesh.hpp"
#include "render/scene_io/mesh_json.hpp"
#include "render/scene_io/scene_json.hpp"
#include "server/mesh_store.hpp"
#include "server/scene_store.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

namespace rr {
namespace {

using nlohmann::json;

// A unit cube as six quads, counter-clockwise seen from outside.
const std::vector<Vec3> cube_vertices = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                         {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
const std::vector<std::vector<uint32_t>> cube_faces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                                       {2, 3, 7, 6}, {0, 4, 7, 3}, {1, 2, 6, 5}};

json cube_json() { return mesh_to_json(*make_mesh_data(cube_vertices, cube_faces, {})); }

InputError mesh_error(const json& document, const ParseLimits& limits = {}) {
  try {
    mesh_from_json(document, limits);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted " << document.dump();
  return InputError(InputError::Kind::invalid, "", "");
}

TEST(MeshData, VertexOrderAndUnusedVerticesDoNotChangeTheId) {
  auto a = make_mesh_data(cube_vertices, cube_faces, {});
  // The same cube with its vertices listed backwards, an unused vertex in front.
  std::vector<Vec3> reversed = {{9, 9, 9}};
  for (size_t i = cube_vertices.size(); i-- > 0;) reversed.push_back(cube_vertices[i]);
  std::vector<std::vector<uint32_t>> faces = cube_faces;
  for (auto& f : faces) {
    for (uint32_t& v : f) v = uint32_t(cube_vertices.size() - v);
  }
  auto b = make_mesh_data(reversed, faces, {});
  EXPECT_EQ(a->content_id, b->content_id);
  EXPECT_EQ(b->vertices.size(), 8u);
  EXPECT_EQ(a->bounds_min, Vec3(0.0));
  EXPECT_EQ(a->bounds_max, Vec3(1.0));
  EXPECT_EQ(a->index_count, 24u);
  std::vector<Vec3> moved = cube_vertices;
  moved[6].y = 1.5;
  EXPECT_NE(make_mesh_data(moved, cube_faces, {})->content_id, a->content_id);
  EXPECT_EQ(mesh_content_id(*a), a->content_id);
}

TEST(MeshJson, RoundTripKeepsTheIdWithNormals) {
  std::vector<Vec3> normals;
  for (const Vec3& v : cube_vertices) normals.push_back(glm::normalize(v - Vec3(0.5)));
  auto mesh = make_mesh_data(cube_vertices, cube_faces, normals);
  auto again = mesh_from_json(json::parse(mesh_to_json(*mesh).dump()), {});
  EXPECT_EQ(again->content_id, mesh->content_id);
  EXPECT_EQ(again->normals, mesh->normals);
}

TEST(MeshJson, ErrorsNameTheirPointer) {
  json doc = cube_json();
  doc["vertices"][3][1] = "x";
  EXPECT_EQ(mesh_error(doc).pointer(), "/vertices/3/1");
  doc = cube_json();
  doc["faces"][5][2] = 8;
  InputError out_of_range = mesh_error(doc);
  EXPECT_EQ(out_of_range.kind(), InputError::Kind::invalid);
  EXPECT_EQ(out_of_range.pointer(), "/faces/5/2");
  doc = cube_json();
  doc["faces"][1] = {0, 1};
  EXPECT_EQ(mesh_error(doc).pointer(), "/faces/1");
  doc = cube_json();
  doc["colour"] = 1;
  EXPECT_EQ(mesh_error(doc).pointer(), "/colour");
  doc = cube_json();
  doc["vertices"][0][0] = 2e7;  // beyond max_abs_coordinate
  EXPECT_EQ(mesh_error(doc).pointer(), "/vertices/0/0");
}

TEST(MeshJson, LimitsAreTooLarge) {
  ParseLimits limits;
  limits.max_polygons = 5;
  InputError faces = mesh_error(cube_json(), limits);
  EXPECT_EQ(faces.kind(), InputError::Kind::too_large);
  EXPECT_EQ(faces.pointer(), "/faces");
  limits = {};
  limits.max_mesh_vertices = 7;
  InputError vertices = mesh_error(cube_json(), limits);
  EXPECT_EQ(vertices.kind(), InputError::Kind::too_large);
  EXPECT_EQ(vertices.pointer(), "/vertices");
}

std::string cube_obj() {
  std::string text = "# a cube\n";
  for (const Vec3& v : cube_vertices)
    text += "v " + std::to_string(int(v.x)) + " " + std::to_string(int(v.y)) + " " + std::to_string(int(v.z)) + "\n";
  text += "g first\n";
  for (size_t f = 0; f < cube_faces.size(); ++f) {
    if (f == 3) text += "g second\n";
    text += "f";
    for (uint32_t v : cube_faces[f]) {
      text += ' ';  // appended apart: GCC 12's -Wrestrict misfires on " " + std::string here
      text += std::to_string(v + 1);
    }
    text += "\n";
  }
  return text;
}

TEST(ObjMesh, SameMeshAsJsonHasTheSameId) {
  std::vector<std::string> warnings;
  auto from_obj = mesh_from_json(obj_mesh_document(cube_obj(), warnings), {});
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(from_obj->content_id, make_mesh_data(cube_vertices, cube_faces, {})->content_id);
}

InputError obj_error(const std::string& text) {
  std::vector<std::string> warnings;
  try {
    obj_mesh_document(text, warnings);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted " << text;
  return InputError(InputError::Kind::invalid, "", "");
}

TEST(ObjMesh, ErrorsNameTheirLine) {
  InputError index = obj_error("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n");
  EXPECT_EQ(index.kind(), InputError::Kind::invalid);
  EXPECT_EQ(index.pointer(), "/line/5");
  EXPECT_EQ(obj_error("v 0 0 0\nv nan 0 0\n").pointer(), "/line/2");
  EXPECT_EQ(obj_error("v 0 0 0\nv 1 0 0\nf 1 2\n").pointer(), "/line/3");
  EXPECT_EQ(obj_error("v 0 0 0\n").pointer(), "");  // nothing to draw
}

// A resolver over a fixed set of meshes, as the server's mesh store gives one.
ParseLimits limits_with(const std::vector<std::shared_ptr<const MeshData>>& meshes) {
  ParseLimits limits;
  limits.resolve_mesh = [meshes](const std::string& id) -> std::shared_ptr<const MeshData> {
    for (const auto& m : meshes) {
      if (m->content_id == id) return m;
    }
    return nullptr;
  };
  return limits;
}

json ref_solid(const std::string& id, Vec3 position, double rotation_y, Vec3 scale) {
  return {{"type", "mesh"},
          {"ref", id},
          {"position", {position.x, position.y, position.z}},
          {"rotation_y", rotation_y},
          {"scale", {scale.x, scale.y, scale.z}}};
}

TEST(MeshRef, ResolvedThroughTheLimitsAndSharedNotCopied) {
  auto cube = make_mesh_data(cube_vertices, cube_faces, {});
  json request = {{"scene",
                   {{"solids",
                     {ref_solid(cube->content_id, Vec3(0.0), 0.0, Vec3(1.0)),
                      ref_solid(cube->content_id, Vec3(3.0), 45.0, Vec3(2.0))}}}}};
  RenderRequest r = request_from_json(request, limits_with({cube}));
  ASSERT_EQ(r.scene.geometry.solids.size(), 2u);
  EXPECT_EQ(r.scene.geometry.solids[0].mesh.get(), cube.get());
  EXPECT_EQ(r.scene.geometry.solids[1].mesh.get(), cube.get());
  EXPECT_EQ(r.scene.geometry.solids[1].mesh_ref, cube->content_id);
}

TEST(MeshRef, MissingOrMixedRefIsInvalidAtItsPointer) {
  auto cube = make_mesh_data(cube_vertices, cube_faces, {});
  json request = {{"scene",
                   {{"solids",
                     {json::parse(R"({"type": "box", "center": [5, 5], "size": [1, 1, 1]})"),
                      ref_solid("00000000000000ff", Vec3(0.0), 0.0, Vec3(1.0))}}}}};
  for (const ParseLimits& limits : {limits_with({cube}), ParseLimits{}}) {
    try {
      request_from_json(request, limits);
      ADD_FAILURE() << "a missing ref was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.kind(), InputError::Kind::invalid);
      EXPECT_EQ(e.pointer(), "/scene/solids/1/ref") << e.summary();
    }
  }
  json mixed = ref_solid(cube->content_id, Vec3(0.0), 0.0, Vec3(1.0));
  mixed["faces"] = json::array();
  try {
    request_from_json({{"scene", {{"solids", {mixed}}}}}, limits_with({cube}));
    ADD_FAILURE() << "ref with faces was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer(), "/scene/solids/0/faces");
  }
}

TEST(MeshRef, SceneIdCoversTheReferencedMesh) {
  auto cube = make_mesh_data(cube_vertices, cube_faces, {});
  std::vector<Vec3> taller = cube_vertices;
  for (Vec3& v : taller) v.y *= 2.0;
  auto tall = make_mesh_data(taller, cube_faces, {});
  const ParseLimits limits = limits_with({cube, tall});
  auto id_of = [&](const json& solid) {
    return scene_id(request_from_json({{"scene", {{"solids", {solid}}}}}, limits).scene.geometry);
  };
  json by_ref = ref_solid(cube->content_id, Vec3(1.0), 0.0, Vec3(1.0));
  json inline_mesh = by_ref;
  inline_mesh.erase("ref");
  inline_mesh.update(cube_json());
  EXPECT_EQ(id_of(by_ref), id_of(inline_mesh));  // the same geometry draws alike
  EXPECT_NE(id_of(by_ref), id_of(ref_solid(tall->content_id, Vec3(1.0), 0.0, Vec3(1.0))));
}

// A mesh's vertices placed as the tessellator places them: scale, rotation_y, position.
std::vector<Vec3> placed(const std::vector<Vec3>& vertices, Vec3 position, double rotation_y_deg, Vec3 scale) {
  const double a = rotation_y_deg * M_PI / 180.0, c = std::cos(a), s = std::sin(a);
  std::vector<Vec3> out;
  for (const Vec3& v : vertices) {
    const Vec3 p = v * scale;
    out.push_back(position + Vec3(c * p.x + s * p.z, p.y, -s * p.x + c * p.z));
  }
  return out;
}

struct Placement {
  Vec3 position;
  double rotation_y;
  Vec3 scale;
};

// Three placements of one shared mesh against three inline copies with pre-placed vertices: the same
// polygons, in order, within rounding (positions 1e-12 of their size, shading normals 1e-5).
TEST(MeshInstancing, ThreePlacementsEqualThreeTransformedCopies) {
  // An L-shaped (non-convex, so ear-clipped) prism with smooth normals: every planned piece counts.
  const Vec2 l_shape[6] = {{0, 0}, {0, 2}, {1, 2}, {1, 1}, {2, 1}, {2, 0}};
  std::vector<Vec3> vertices;
  for (double y : {0.0, 1.0}) {
    for (Vec2 p : l_shape) vertices.push_back({p.x, y, p.y});
  }
  std::vector<std::vector<uint32_t>> faces = {{0, 5, 4, 3, 2, 1}, {6, 7, 8, 9, 10, 11}};
  for (uint32_t i = 0; i < 6; ++i) faces.push_back({i, (i + 1) % 6, (i + 1) % 6 + 6, i + 6});
  auto shared = make_mesh_data(vertices, faces, {});
  const Placement placements[3] = {
      {{0, 0, 0}, 0.0, {1, 1, 1}}, {{5, 1, -2}, 30.0, {1, 2, 0.5}}, {{-4, 0, 3}, 200.0, {0.3, 0.3, 0.3}}};
  StaticGeometry instanced, copies;
  for (const Placement& p : placements) {
    Solid s;
    s.type = SolidType::mesh;
    s.smooth = true;
    s.closed = true;
    s.mesh = shared;
    s.position = p.position, s.rotation_y_deg = p.rotation_y, s.scale = p.scale;
    instanced.solids.push_back(s);
    Solid copy = s;
    copy.position = Vec3(0.0), copy.rotation_y_deg = 0.0, copy.scale = Vec3(1.0);
    copy.mesh = make_mesh_data(placed(vertices, p.position, p.rotation_y, p.scale), faces, {});
    copies.solids.push_back(copy);
  }
  const PolygonSoup a = tessellate(instanced), b = tessellate(copies);
  ASSERT_EQ(a.polygons.size(), b.polygons.size());
  EXPECT_EQ(a.polygons.size(), 3u * (4 + 4 + 6));  // each L cap becomes 4 triangles
  for (size_t i = 0; i < a.polygons.size(); ++i) {
    const Polygon &pa = a.polygons[i], &pb = b.polygons[i];
    ASSERT_EQ(pa.vertex_count, pb.vertex_count) << "polygon " << i;
    EXPECT_EQ(pa.object, pb.object);
    EXPECT_NEAR(glm::dot(pa.normal, pb.normal), 1.0, 1e-12) << "polygon " << i;
    for (uint32_t k = 0; k < pa.vertex_count; ++k) {
      EXPECT_NEAR(glm::length(a.points(pa)[k] - b.points(pb)[k]), 0.0, 1e-12 * 10.0) << "polygon " << i;
      EXPECT_NEAR(glm::length(a.vertex_normals(pa)[k] - b.vertex_normals(pb)[k]), 0.0f, 1e-5f) << "polygon " << i;
    }
  }
  // The per-mesh work is made once and kept for the next scene that places the mesh.
  ASSERT_TRUE(shared->plan);
  const void* plan = shared->plan.get();
  tessellate(instanced);
  EXPECT_EQ(shared->plan.get(), plan);
}

// A stored scene pins the stored meshes it places: the mesh's last reference cannot be released
// until the scene is gone, and a stored mesh's text reads back to the same id.
TEST(MeshStore, PinnedWhileAStoredScenePlacesIt) {
  server::MeshPins pins;
  server::MeshStoreConfig config;
  config.kind = "mesh", config.plural = "meshes";
  config.pinned = [&pins](const std::string& id) { return pins.pinned(id); };
  server::MeshStore meshes(config, [](const std::string&, nlohmann::ordered_json) {});
  auto cube = server::prepare_mesh(make_mesh_data(cube_vertices, cube_faces, {}));
  EXPECT_EQ(server::read_stored_mesh(cube->text, {})->id, cube->id);
  EXPECT_EQ(server::read_mesh_document(cube->text, {}).id, cube->id);
  ASSERT_EQ(meshes.put(server::mesh_document(*cube), "a"), server::MeshStore::PutResult::created);
  ASSERT_EQ(meshes.put(server::mesh_document(*cube), "b"), server::MeshStore::PutResult::existed);
  const std::string scene = "00000000000000aa";
  pins.change(scene, {cube->id}, true);
  EXPECT_EQ(pins.scenes_placing(cube->id, 5), std::vector<std::string>{scene});
  EXPECT_EQ(meshes.release(cube->id, "a"), server::MeshStore::ReleaseResult::reference_dropped);
  EXPECT_EQ(meshes.release(cube->id, "b"), server::MeshStore::ReleaseResult::pinned);
  EXPECT_EQ(meshes.find(cube->id, true), cube->text);
  pins.change(scene, {cube->id}, false);
  EXPECT_FALSE(pins.pinned(cube->id));
  EXPECT_EQ(meshes.release(cube->id, "b"), server::MeshStore::ReleaseResult::removed);
  EXPECT_FALSE(meshes.find(cube->id, false));
}

}  // namespace
}  // namespace rr
