// Solid type "mesh": indexed faces in object space, placed by scale, then rotation_y, then
// position. Closed and smooth only when the request says so (or gives per-vertex normals).
#include "render/core/solids.hpp"
#include "render/core/tessellate_detail.hpp"

#include <algorithm>
#include <vector>

namespace rr::detail {

namespace {

// A mesh's given normal in world space: the inverse transpose of scale, then rotation_y.
glm::vec3 mesh_normal_to_world(const Solid& s, Vec3 n, double angle_rad) {
  const Vec3 scaled = n / s.scale;
  const Vec2 xz = rotate_plan({scaled.x, scaled.z}, angle_rad);
  return glm::vec3(glm::normalize(Vec3(xz.x, scaled.y, xz.y)));
}

// One polygon per face (triangles for non-convex faces). Object space -> world: scale, then
// rotate_y, then translate. A mirroring scale would turn faces inside out, so it reverses them.
void add_mesh(SoupBuilder& out, const Solid& s, uint32_t material, uint32_t object) {
  const double a = radians(s.rotation_y_deg);
  std::vector<Vec3> world(s.vertices.size());
  for (size_t i = 0; i < world.size(); ++i) {
    const Vec3 scaled = s.vertices[i] * s.scale;
    const Vec2 xz = rotate_plan({scaled.x, scaled.z}, a);
    world[i] = s.position + Vec3(xz.x, scaled.y, xz.y);
  }
  const bool mirrored = s.scale.x * s.scale.y * s.scale.z < 0.0;
  std::vector<std::vector<Vec3>> faces(s.faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    for (uint32_t v : s.faces[f]) faces[f].push_back(world[v]);
    if (mirrored) std::reverse(faces[f].begin(), faces[f].end());
  }
  // Smooth: each vertex averages the Newell vectors (2 * area * normal) of the faces using it.
  std::vector<Vec3> vertex_sum(s.smooth ? world.size() : 0, Vec3(0.0));
  if (s.smooth) {
    for (size_t f = 0; f < faces.size(); ++f) {
      const Vec3 n = newell_vector(faces[f]);
      for (uint32_t v : s.faces[f]) vertex_sum[v] += n;
    }
  }
  std::vector<glm::vec3> shading;
  for (size_t f = 0; f < faces.size(); ++f) {
    const Vec3 n = newell_vector(faces[f]);
    shading.clear();
    if (!s.normals.empty()) {
      std::vector<uint32_t> ids = s.faces[f];
      if (mirrored) std::reverse(ids.begin(), ids.end());
      for (uint32_t v : ids) shading.push_back(mesh_normal_to_world(s, s.normals[v], a));
    } else if (s.smooth) {
      std::vector<uint32_t> ids = s.faces[f];
      if (mirrored) std::reverse(ids.begin(), ids.end());
      for (uint32_t v : ids) {
        const double len = glm::length(vertex_sum[v]);
        shading.push_back(glm::vec3(len > 0.0 ? vertex_sum[v] / len : glm::normalize(n)));
      }
    }
    if (glm::length(n) > 0.0) add_face(out, faces[f], shading, n, material, object);
  }
}

// A face of k vertices becomes at most k - 2 triangles.
size_t estimate_mesh(const Solid& s) {
  size_t count = 0;
  for (const auto& f : s.faces) count += f.size() > 2 ? f.size() - 2 : 1;
  return count;
}

}  // namespace

extern const SolidInfo mesh_solid = {SolidType::mesh, "mesh", add_mesh, estimate_mesh,
                                     [](const Solid& s) { return s.closed; },
                                     [](const Solid& s) { return s.smooth || !s.normals.empty(); }};

}  // namespace rr::detail
