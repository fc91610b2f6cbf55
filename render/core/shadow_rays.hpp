// The pipelines' shadow rays: a four-wide bounding-volume hierarchy of one static soup's shadow
// casters (every polygon that is not translucent), collapsed from its SceneHierarchy (binned SAH,
// hierarchy.hpp) and traversed four boxes at a time in floats, any hit ending the walk. A second
// tree of the same kind holds the translucent polygons (window panes): they do not block a ray but
// let through pane_transmittance of the light, so a ray that no caster blocks is tinted by the
// product over every pane it crosses. Boxes are
// padded so that float rounding of the ray never loses a box the exact ray enters; the polygons are
// then tested in doubles with intersect_polygon and the casters of shadow.cpp (as the reference's
// shadow rays are), so a ray's answer is exactly the brute-force search's, whatever the traversal
// order, the thread or the SIMD level. It is not the reference's BVH (bvh.hpp), which stays the oracle's.
#pragma once

#include "render/core/hierarchy.hpp"
#include "render/core/math.hpp"
#include "render/core/scene.hpp"
#include "render/core/tessellate.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace rr {

// Four children, boxes as structure of arrays. child[i] >= 0: an inner node; < 0: leaf ~child[i]
// (ShadowBvh::leaf_begin); an empty slot has an empty box (lo > hi), which no ray enters.
struct alignas(16) ShadowBvhNode {
  float lo[3][4], hi[3][4];
  int32_t child[4];
};

struct ShadowBvhTree {
  std::vector<ShadowBvhNode> nodes;  // nodes[0] is the root; empty when the tree holds no polygon
  std::vector<uint32_t> leaf_begin;  // leaf l holds items[leaf_begin[l], leaf_begin[l + 1])
  std::vector<uint32_t> items;       // soup polygon indices
  size_t depth = 0;                  // levels of nodes (the traversal's stack holds 3 per level)
};

// What the exact test of a ray against item i of the casters' tree reads, copied from the soup in
// the items' order, so that a leaf's polygons lie side by side: the plane, the axes of the plane its
// inside test projects onto (intersect_polygon's choice) and the vertices' coordinates on them.
struct ShadowCaster {
  Vec3 normal{0.0};
  double offset = 0.0;
  uint32_t id = 0;                // Polygon::id
  uint32_t first = 0, count = 0;  // into ShadowBvh::projected
  uint8_t u = 0, v = 0;           // the two axes kept
  bool closed = false;            // polygon_closed
  bool positive = true;           // the dropped axis's normal component is >= 0
};

// The opaque casters' tree (its own members), and the panes' tree beside it.
struct ShadowBvh : ShadowBvhTree {
  std::vector<ShadowCaster> casters;  // per item of the casters' tree
  std::vector<glm::dvec2> projected;  // the casters' vertices on their (u, v) axes, in order
  ShadowBvhTree glass;                // translucent polygons; empty when the soup has none
  double ray_epsilon = 0.0;           // shadow rays start this far from their surface point
  size_t bytes() const;               // what both trees cost against a cache budget
};

// The casters' and the panes' trees of `soup` from its hierarchy (subtrees without a polygon of a
// tree are left out of it). Deterministic; linear in the hierarchy's size.
ShadowBvh build_shadow_bvh(const PolygonSoup& soup, const SceneHierarchy& hierarchy);

// The fraction of light, per channel, that a pane of `material` lets through: (1 - opacity) of it,
// tinted by the pane's colour scaled to a maximum of 1 (a clear pane's white passes everything its
// opacity lets through; a green one passes the green of it). 0 for a black pane.
inline glm::dvec3 pane_transmittance(const Material& material) {
  const glm::dvec3 c(material.color);
  const double top = std::max({c.r, c.g, c.b});
  if (!(top > 0.0)) return glm::dvec3(0.0);
  return (1.0 - std::clamp(double(material.opacity), 0.0, 1.0)) * (c / top);
}

// Whether a caster other than the polygon whose id is `self` (Polygon::id: the source polygon's index
// in the tessellated soup, which a view's selection and a pipeline's fragments keep) blocks the segment from p toward
// `light` (to its position for a point light, without end for a directional one), as the reference's shadow ray decides
// it: the ray starts bvh.ray_epsilon from p (and stops as far before a point light); casters are opaque polygons not
// edge-on to the light and, for closed objects, only the faces turned away from it. A point light within 2 epsilon of p
// is never blocked.
//
// `memo` (optional, one per thread and light): the casters that blocked the last few blocked rays,
// tested before the tree, most recent first; a blocker found moves to the front. Any caster that blocks the segment
// proves the answer, so the memo changes the cost, never the answer. `stats` (optional) counts the work.
struct ShadowRayMemo {
  static constexpr size_t size = 4;
  // Items of the casters' tree (ShadowBvh::casters), or none: the last blocker first, then older ones.
  uint32_t blocker = UINT32_MAX;
  std::array<uint32_t, size - 1> older{UINT32_MAX, UINT32_MAX, UINT32_MAX};
};
struct ShadowRayStats {
  uint64_t rays = 0, blocked = 0, memo_hits = 0, nodes = 0, polygons = 0;
};
bool shadow_ray_blocked(const ShadowBvh& bvh, uint32_t self, Vec3 p, const Light& light, ShadowRayMemo* memo = nullptr,
                        ShadowRayStats* stats = nullptr);

// The light that reaches p from `light` through the panes on the same segment (the same epsilon, the
// same own-id exclusion, and the casters' rule for which faces count: a closed pane counts once):
// the product of pane_transmittance over every pane the segment crosses, 1 where it crosses none.
// Says nothing about the opaque casters: a pixel's light is its visibility times this.
Color shadow_ray_transmittance(const ShadowBvh& bvh, const PolygonSoup& soup, uint32_t self, Vec3 p,
                               const Light& light);

// The same by testing every polygon of `soup` (the tests' oracle).
bool shadow_ray_blocked_brute_force(const PolygonSoup& soup, double ray_epsilon, uint32_t self, Vec3 p,
                                    const Light& light);
Color shadow_ray_transmittance_brute_force(const PolygonSoup& soup, double ray_epsilon, uint32_t self, Vec3 p,
                                           const Light& light);

// The directions around a point light that its own fixture closes: a bin of directions (one of
// n x n squares on each face of a cube about the light) is closed when one convex, planar caster of
// the light (polygons of the soup near it, by the rule above) lies within `reach` of the light and is
// crossed by all four of the bin's corner rays at least `margin` inside its edges, and its plane lies
// more than `margin` from the light (planar: its vertices within margin / 1000 of its plane). Then every ray from the
// light with a direction in the bin crosses that polygon within reach (the bin's cross-section with its plane is the
// convex hull of the corner hits), so a segment from a point farther than reach + margin to the light is blocked (the
// segment cannot start on that polygon, all of whose points are within reach).
struct FixtureMap {
  Vec3 light{0.0};
  double far2 = 0.0;  // (reach + margin)^2: closes() answers only for points farther than this
  int n = 0;          // bins per cube face edge; 0: no bin closed
  std::vector<uint64_t> bits;
  // Whether every shadow ray from p to the light is blocked by the fixture. Only a closed bin
  // answers true, and a closed bin's proof holds for directions far beyond the rounding of u and v
  // (its corner rays meet the caster `margin` inside its edges), so how u and v are rounded (one
  // reciprocal here) moves no answer from a blocked ray to an unblocked one.
  bool closes(Vec3 p) const {
    if (n == 0) return false;
    const Vec3 d = p - light;
    if (!(glm::dot(d, d) > far2)) return false;
    const double ax = std::abs(d.x), ay = std::abs(d.y), az = std::abs(d.z);
    int face = 0;
    double w = 0.0, du = 0.0, dv = 0.0;  // the dominant axis's extent and the other two (b, c) of face
    if (ax >= ay && ax >= az) {
      face = d.x < 0.0, w = ax, du = d.y, dv = d.z;
    } else if (ay >= az) {
      face = 2 + (d.y < 0.0), w = ay, du = d.z, dv = d.x;
    } else {
      face = 4 + (d.z < 0.0), w = az, du = d.x, dv = d.y;
    }
    const double half_n = 0.5 * n, r = 1.0 / w;
    const int i = std::clamp(int((du * r + 1.0) * half_n), 0, n - 1),
              j = std::clamp(int((dv * r + 1.0) * half_n), 0, n - 1);
    const size_t bin = (size_t(face) * size_t(n) + size_t(j)) * size_t(n) + size_t(i);
    return (bits[bin / 64] >> (bin % 64)) & 1u;
  }
};
// The fixture map of `light` (a point light) from `polygons` (indices into `soup`).
FixtureMap fixture_map(const PolygonSoup& soup, std::span<const uint32_t> polygons, const Light& light, double margin,
                       int n);

// The reference's ray epsilon for `soup`: 1e-9 of its size plus 1e-12 of its distance from the origin.
double shadow_ray_epsilon(const PolygonSoup& soup);

}  // namespace rr
