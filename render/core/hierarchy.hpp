// The pipelines' bounding-volume hierarchy of one static polygon soup (world space): a binary tree
// built once per scene with the binned surface-area heuristic, whose leaves are small clusters of
// polygons. Nodes are numbered depth first (a node's first child follows it), so the polygons below
// any node are one contiguous range of `polygons`: a walk can take a whole subtree without visiting
// it. Boxes are floats rounded outward, so every node's box holds every polygon below it exactly.
// The occlusion walk (occlusion.hpp) reads it front to back; a ray caster can read it as it is or
// collapse it into wider nodes. It is not the reference's BVH (bvh.hpp), which stays the oracle's.
#pragma once

#include "render/core/cancel.hpp"
#include "render/core/math.hpp"
#include "render/core/tessellate.hpp"

#include <cstdint>
#include <vector>

namespace rr {

struct HierarchyNode {
  glm::vec3 lo{0.0f}, hi{0.0f};  // holds every polygon below (rounded outward from the doubles)
  uint32_t first = 0;            // the polygons below: SceneHierarchy::polygons[first, first + count)
  uint32_t count = 0;
  uint32_t second = 0;  // inner node: index of its second child (the first is this index + 1); 0: a leaf
  bool leaf() const { return second == 0; }
};

// A polygon's bounding sphere (centre and radius in metres), for a cheap screen-size estimate.
struct PolygonSphere {
  glm::vec3 centre{0.0f};
  float radius = 0.0f;  // rounded up: the sphere holds the polygon
};

struct SceneHierarchy {
  std::vector<HierarchyNode> nodes;    // nodes[0] is the root; empty for a soup without polygons
  std::vector<uint32_t> polygons;      // soup polygon indices, grouped by leaf
  std::vector<PolygonSphere> spheres;  // per soup polygon index
  size_t bytes() const;                // what it costs against a cache budget
};

// Leaves hold at most this many polygons (fewer when the surface-area heuristic says so).
constexpr uint32_t hierarchy_leaf_max = 16;

// Builds the hierarchy of `soup`. Deterministic: the same soup gives the same tree. Throws
// RenderCancelled when `cancel` expires (a frame that builds its own).
SceneHierarchy build_hierarchy(const PolygonSoup& soup, const CancelToken* cancel = nullptr);

}  // namespace rr
