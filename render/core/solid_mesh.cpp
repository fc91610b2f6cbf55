// Solid type "mesh": a shared MeshData (object space) placed by scale, then rotation_y, then
// position, through add_placed_mesh, which a piece's parts share. Closed and smooth only when the
// request says so (or gives per-vertex normals). The per-mesh work (face areas, convexity, ear clipping, smooth-normal
// sums) is a MeshPlan made once per MeshData; each placement only transforms vertices and normals and emits the planned
// pieces.
#include "render/core/solids.hpp"
#include "render/core/tessellate_detail.hpp"

#include <array>
#include <vector>

namespace rr::detail {

struct MeshPlan {
  struct Face {
    uint32_t face = 0;            // into MeshData::faces; faces without area are not planned
    Vec3 newell{0.0};             // object space
    uint32_t first_triangle = 0;  // into triangles; no triangles: the face is one polygon
    uint32_t triangle_count = 0;
  };
  std::vector<Face> faces;
  std::vector<std::array<uint32_t, 3>> triangles;  // corners of a face, indices into that face
  std::vector<Vec3> vertex_sum;                    // per vertex, the Newell vectors (2 * area * normal) of its faces
};

namespace {

std::shared_ptr<const MeshPlan> make_plan(const MeshData& mesh) {
  auto plan = std::make_shared<MeshPlan>();
  plan->vertex_sum.assign(mesh.vertices.size(), Vec3(0.0));
  std::vector<Vec3> points;
  std::vector<std::array<uint32_t, 3>> triangles;
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    points.clear();
    for (uint32_t v : mesh.faces[f]) points.push_back(mesh.vertices[v]);
    const Vec3 n = newell_vector(points);
    for (uint32_t v : mesh.faces[f]) plan->vertex_sum[v] += n;
    if (!split_face(points, triangles)) continue;
    plan->faces.push_back({uint32_t(f), n, uint32_t(plan->triangles.size()), uint32_t(triangles.size())});
    plan->triangles.insert(plan->triangles.end(), triangles.begin(), triangles.end());
  }
  return plan;
}

const MeshPlan& plan_of(const MeshData& mesh) {
  std::call_once(mesh.plan_once, [&] { mesh.plan = make_plan(mesh); });
  return *mesh.plan;
}

// A placement's maps of points and of normals, object space -> world.
class Placed {
 public:
  explicit Placed(const MeshPlacement& place) : place_(place) {
    if (place.pre) normal_linear_ = glm::transpose(glm::inverse(place.pre->linear));
  }

  // Scale, then rotate_y, then translate (after the part's affine step, if any).
  Vec3 point(Vec3 p) const {
    if (place_.pre) p = place_.pre->linear * p + place_.pre->offset;
    const Vec3 scaled = p * place_.scale;
    const Vec2 xz = rotate_plan({scaled.x, scaled.z}, place_.rotation_y_rad);
    return place_.position + Vec3(xz.x, scaled.y, xz.y);
  }

  // The inverse transpose of the same steps (not normalised). It keeps the direction an
  // area-weighted normal takes, so object-space sums transform as sums.
  Vec3 normal(Vec3 n) const {
    if (place_.pre) n = normal_linear_ * n;
    const Vec3 scaled = n / place_.scale;
    const Vec2 xz = rotate_plan({scaled.x, scaled.z}, place_.rotation_y_rad);
    return Vec3(xz.x, scaled.y, xz.y);
  }

 private:
  const MeshPlacement& place_;
  Mat3 normal_linear_{1.0};
};

// Per vertex shading normals of one placement: the given ones, or the smooth sums; zero where a
// vertex has no sum (its faces then use their own normal). Empty when faceted.
std::vector<glm::vec3> placed_shading(const MeshData& mesh, const MeshPlan& plan, const Placed& placed, bool smooth) {
  const std::vector<Vec3>* source = !mesh.normals.empty() ? &mesh.normals : (smooth ? &plan.vertex_sum : nullptr);
  std::vector<glm::vec3> out;
  if (!source) return out;
  out.reserve(source->size());
  for (const Vec3& n : *source) {
    const Vec3 w = placed.normal(n);
    const double len = glm::length(w);
    out.push_back(len > 0.0 ? glm::vec3(w / len) : glm::vec3(0.0f));
  }
  return out;
}

void add_mesh(SoupBuilder& out, const Solid& s, uint32_t material, uint32_t object) {
  const MeshPlacement place{s.position, radians(s.rotation_y_deg), s.scale, nullptr};
  add_placed_mesh(out, *s.mesh, place, s.smooth, material, object);
}

size_t estimate_mesh(const Solid& s) { return estimate_mesh_polygons(*s.mesh); }

}  // namespace

void add_placed_mesh(SoupBuilder& out, const MeshData& mesh, const MeshPlacement& place, bool smooth, uint32_t material,
                     uint32_t object) {
  const MeshPlan& plan = plan_of(mesh);
  const Placed placed(place);
  std::vector<Vec3> world(mesh.vertices.size());
  for (size_t i = 0; i < world.size(); ++i) world[i] = placed.point(mesh.vertices[i]);
  const std::vector<glm::vec3> vertex_shading = placed_shading(mesh, plan, placed, smooth);
  // Per-vertex texture coordinates matter only under a textured material; without them a textured
  // mesh takes the texture's planar mapping.
  const bool uvs = !mesh.uvs.empty() && out.textured(material);
  std::vector<Vec3> points;
  std::vector<glm::vec3> shading;
  std::vector<glm::dvec2> face_uvs;
  for (const MeshPlan::Face& f : plan.faces) {
    const Vec3 outward = placed.normal(f.newell);
    points.clear();
    shading.clear();
    face_uvs.clear();
    for (uint32_t v : mesh.faces[f.face]) {
      points.push_back(world[v]);
      if (uvs) face_uvs.push_back(mesh.uvs[v]);
      if (vertex_shading.empty()) continue;
      const glm::vec3 n = vertex_shading[v];
      shading.push_back(n != glm::vec3(0.0f) ? n : glm::vec3(glm::normalize(outward)));
    }
    const std::span<const std::array<uint32_t, 3>> triangles(plan.triangles.data() + f.first_triangle,
                                                             f.triangle_count);
    add_face_pieces(out, points, shading, triangles, outward, material, object, face_uvs);
  }
}

size_t estimate_mesh_polygons(const MeshData& mesh) { return mesh.index_count - 2 * mesh.faces.size(); }

extern const SolidInfo mesh_solid = {SolidType::mesh,
                                     "mesh",
                                     add_mesh,
                                     estimate_mesh,
                                     [](const Solid& s) { return s.closed; },
                                     [](const Solid& s) { return s.smooth || !s.mesh->normals.empty(); }};

}  // namespace rr::detail
