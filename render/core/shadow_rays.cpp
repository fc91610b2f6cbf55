// The four-wide shadow-ray tree (see shadow_rays.hpp): built by collapsing the binary hierarchy,
// each node taking the grandchildren of its largest inner children until it has four; traversed
// with an explicit stack, four slab tests at once (SSE2, the x86-64 baseline, so every CPU runs the
// same instructions), leaves tested in doubles.
#include "render/core/shadow_rays.hpp"

#include "render/core/ray_polygon.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace rr {

namespace {

constexpr float inf_f = std::numeric_limits<float>::infinity();

// Whether a polygon with this plane casts a shadow of `light` (shadow.cpp's caster_side): not
// edge-on to it, and for a closed object only when it faces away from it (the same silhouette, half
// the faces).
bool casts_shadow(Vec3 normal, double offset, bool closed, const Light& light) {
  const double facing = light.type == LightType::directional ? glm::dot(normal, light.direction)
                                                             : offset - glm::dot(normal, light.position);
  return facing != 0.0 && !(closed && facing < 0.0);
}
bool casts_shadow(const Polygon& q, const Light& light) {
  return casts_shadow(q.normal, q.offset, (q.flags & polygon_closed) != 0, light);
}

struct Segment {
  Vec3 direction;
  double t_min, t_max;
  bool empty;  // a point light too close to p: never blocked
};

Segment segment_toward(Vec3 p, const Light& light, double eps) {
  if (light.type == LightType::directional) {
    return {-light.direction, eps, std::numeric_limits<double>::infinity(), false};
  }
  const Vec3 direction = light.position - p;
  const double distance = glm::length(direction);
  if (!(distance > 2.0 * eps)) return {direction, 0.0, 0.0, true};
  const double t_min = eps / distance;
  return {direction, t_min, 1.0 - t_min, false};
}

// casts_shadow and intersect_polygon on a packed caster: intersect_polygon's steps (ray_polygon.hpp:
// ray_plane_t, then inside_projected on the axes inside_axes chose at build time) written out here,
// the same arithmetic in the same order, so the same answer bit for bit. Written out because the
// shared helpers, called here, cost 6-8 % of a furnished home's frame with rays.
bool caster_blocks(const ShadowBvh& bvh, const ShadowCaster& q, const Light& light, Vec3 origin, const Segment& s) {
  const double facing = light.type == LightType::directional ? glm::dot(q.normal, light.direction)
                                                             : q.offset - glm::dot(q.normal, light.position);
  if (!(facing != 0.0 && !(q.closed && facing < 0.0))) return false;
  const double denom = glm::dot(q.normal, s.direction);
  if (denom == 0.0) return false;
  const double t = (q.offset - glm::dot(q.normal, origin)) / denom;
  if (!(t > s.t_min && t < s.t_max)) return false;
  const Vec3 p = origin + t * s.direction;
  const double sign = q.positive ? 1.0 : -1.0;
  if (q.count == 0) return true;
  const glm::dvec2* e = bvh.projected.data() + q.first;
  const double pu = p[q.u], pv = p[q.v];
  glm::dvec2 start = e[q.count - 1];
  for (uint32_t k = 0; k < q.count; ++k) {
    const double cross = (e[k].x - start.x) * (pv - start.y) - (e[k].y - start.y) * (pu - start.x);
    if (sign * cross < 0.0) return false;
    start = e[k];
  }
  return true;
}

// The first caster of the leaf that blocks the segment (an item of the casters' tree), or UINT32_MAX.
uint32_t leaf_blocker(const ShadowBvh& bvh, uint32_t leaf, uint32_t self, Vec3 p, const Light& light, const Segment& s,
                      ShadowRayStats* stats) {
  for (uint32_t i = bvh.leaf_begin[leaf]; i < bvh.leaf_begin[leaf + 1]; ++i) {
    const ShadowCaster& q = bvh.casters[i];
    if (q.id == self) continue;
    if (stats) ++stats->polygons;
    if (caster_blocks(bvh, q, light, p, s)) return i;
  }
  return UINT32_MAX;
}

// Bits i of the children whose (padded) boxes the ray enters within [0, t_far]. A slab product that
// is NaN (0 x infinity: the origin on a slab of an axis the ray runs parallel to) is left out of the
// interval, which only keeps a box.
struct FloatRay {
  float origin[3], inv[3], t_far;
  bool negative[3];
};

#if defined(__SSE2__)
int entered(const ShadowBvhNode& node, const FloatRay& r) {
  __m128 t0 = _mm_setzero_ps(), t1 = _mm_set1_ps(r.t_far);
  for (int a = 0; a < 3; ++a) {
    const __m128 o = _mm_set1_ps(r.origin[a]), inv = _mm_set1_ps(r.inv[a]);
    const __m128 lo = _mm_load_ps(node.lo[a]), hi = _mm_load_ps(node.hi[a]);
    const __m128 near = _mm_mul_ps(_mm_sub_ps(r.negative[a] ? hi : lo, o), inv);
    const __m128 far = _mm_mul_ps(_mm_sub_ps(r.negative[a] ? lo : hi, o), inv);
    t0 = _mm_max_ps(near, t0);  // NaN in `near` gives t0
    t1 = _mm_min_ps(far, t1);   // NaN in `far` gives t1
  }
  return _mm_movemask_ps(_mm_cmple_ps(t0, t1));
}
#else
int entered(const ShadowBvhNode& node, const FloatRay& r) {
  int bits = 0;
  for (int i = 0; i < 4; ++i) {
    float t0 = 0.0f, t1 = r.t_far;
    for (int a = 0; a < 3; ++a) {
      const float near = ((r.negative[a] ? node.hi[a][i] : node.lo[a][i]) - r.origin[a]) * r.inv[a];
      const float far = ((r.negative[a] ? node.lo[a][i] : node.hi[a][i]) - r.origin[a]) * r.inv[a];
      t0 = near > t0 ? near : t0;
      t1 = far < t1 ? far : t1;
    }
    bits |= int(t0 <= t1) << i;
  }
  return bits;
}
#endif

// Calls leaf(l) for each leaf of `tree` whose box the segment from p enters, depth first, until one
// returns true; returns whether one did. Depth-first: each level leaves at most 3 entries on the
// stack, so 3 x depth + 1 hold it; a tree too deep for the fixed stack (a degenerate soup) takes
// the thread's growing one.
template <class Leaf>
bool walk(const ShadowBvhTree& tree, Vec3 p, const Segment& s, ShadowRayStats* stats, Leaf&& leaf) {
  if (tree.nodes.empty()) return false;
  FloatRay r;
  for (int a = 0; a < 3; ++a) {
    r.origin[a] = float(p[a]);
    r.inv[a] = 1.0f / float(s.direction[a]);  // +-infinity where the ray runs parallel to the slabs
    r.negative[a] = std::signbit(r.inv[a]);
  }
  r.t_far = s.t_max == std::numeric_limits<double>::infinity() ? inf_f : float(s.t_max) * (1.0f + 1e-6f);
  std::array<int32_t, 256> fixed;
  thread_local std::vector<int32_t> deep;
  int32_t* stack = fixed.data();
  if (3 * tree.depth + 1 > fixed.size()) deep.resize(3 * tree.depth + 1), stack = deep.data();
  size_t top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const ShadowBvhNode& node = tree.nodes[size_t(stack[--top])];
    if (stats) ++stats->nodes;
    for (int bits = entered(node, r); bits != 0; bits &= bits - 1) {
      const int32_t child = node.child[__builtin_ctz(unsigned(bits))];
      if (child >= 0) {
        stack[top++] = child;
      } else if (leaf(uint32_t(~child))) {
        return true;
      }
    }
  }
  return false;
}

// Whether pane q lets through less than all of the segment's light: it crosses the segment and
// counts by the casters' rule.
bool crosses_pane(const PolygonSoup& soup, const Polygon& q, const Light& light, Vec3 p, const Segment& s) {
  return casts_shadow(q, light) && intersect_polygon(soup, q, p, s.direction, s.t_min, s.t_max);
}

}  // namespace

double shadow_ray_epsilon(const PolygonSoup& soup) {
  Vec3 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const Vec3& p : soup.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  if (soup.positions.empty()) return 1e-9;  // the reference's scene size of 1 for an empty soup
  return 1e-9 * glm::length(hi - lo) + 1e-12 * std::max(glm::length(lo), glm::length(hi));
}

namespace {

// One tree of build_shadow_bvh: the polygons for which `keep` holds, under the hierarchy's nodes
// that have at least one of them.
template <class Keep>
ShadowBvhTree build_tree(const SceneHierarchy& hierarchy, double pad, Keep&& keep) {
  ShadowBvhTree tree;
  tree.leaf_begin.push_back(0);
  // Whether a node has a kept polygon below it: children follow their parent, so a backward pass
  // sees them first.
  std::vector<uint8_t> has(hierarchy.nodes.size(), 0);
  for (size_t h = hierarchy.nodes.size(); h-- > 0;) {
    const HierarchyNode& n = hierarchy.nodes[h];
    if (n.leaf()) {
      for (uint32_t j = n.first; j < n.first + n.count && !has[h]; ++j) has[h] = keep(hierarchy.polygons[j]);
    } else {
      has[h] = has[h + 1] || has[n.second];
    }
  }
  if (has.empty() || !has[0]) return tree;
  auto area = [](const HierarchyNode& n) {
    const glm::vec3 e = n.hi - n.lo;
    return e.x * e.y + e.y * e.z + e.z * e.x;
  };
  struct Work {
    uint32_t hierarchy_node, node, depth;
  };
  std::vector<Work> work{{0u, 0u, 1u}};
  tree.nodes.emplace_back();
  while (!work.empty()) {
    const auto [h, n, depth] = work.back();
    work.pop_back();
    tree.depth = std::max(tree.depth, size_t(depth));
    std::array<uint32_t, 4> kids{};
    size_t count = 0;
    auto add = [&](uint32_t kid) {
      if (has[kid]) kids[count++] = kid;
    };
    if (hierarchy.nodes[h].leaf()) {
      add(h);
    } else {
      add(h + 1), add(hierarchy.nodes[h].second);
    }
    while (count < 4) {  // open the largest inner child
      size_t best = count;
      for (size_t i = 0; i < count; ++i) {
        const HierarchyNode& k = hierarchy.nodes[kids[i]];
        if (!k.leaf() && (best == count || area(k) > area(hierarchy.nodes[kids[best]]))) best = i;
      }
      if (best == count) break;
      const uint32_t opened = kids[best];
      const uint32_t first = opened + 1, second = hierarchy.nodes[opened].second;
      if (has[first] && has[second]) {
        kids[best] = first, kids[count++] = second;
      } else {
        kids[best] = has[first] ? first : second;  // one side only: it takes the opened node's slot
      }
    }
    ShadowBvhNode node;
    for (int a = 0; a < 3; ++a)
      std::fill(node.lo[a], node.lo[a] + 4, inf_f), std::fill(node.hi[a], node.hi[a] + 4, -inf_f);
    std::fill(node.child, node.child + 4, -1);
    for (size_t i = 0, slot = 0; i < count; ++i) {
      const HierarchyNode& k = hierarchy.nodes[kids[i]];
      if (k.leaf()) {
        const size_t before = tree.items.size();
        for (uint32_t j = k.first; j < k.first + k.count; ++j) {
          const uint32_t polygon = hierarchy.polygons[j];
          if (keep(polygon)) tree.items.push_back(polygon);
        }
        if (tree.items.size() == before) continue;  // holds nothing: an empty slot
        node.child[slot] = ~int32_t(tree.leaf_begin.size() - 1);
        tree.leaf_begin.push_back(uint32_t(tree.items.size()));
      } else {
        node.child[slot] = int32_t(tree.nodes.size());
        work.push_back({kids[i], uint32_t(tree.nodes.size()), depth + 1});
        tree.nodes.emplace_back();
      }
      for (int a = 0; a < 3; ++a) {
        node.lo[a][slot] = std::nextafter(float(double(k.lo[a]) - pad), -inf_f);
        node.hi[a][slot] = std::nextafter(float(double(k.hi[a]) + pad), inf_f);
      }
      ++slot;
    }
    tree.nodes[n] = node;
  }
  return tree;
}

}  // namespace

ShadowBvh build_shadow_bvh(const PolygonSoup& soup, const SceneHierarchy& hierarchy) {
  ShadowBvh bvh;
  bvh.ray_epsilon = shadow_ray_epsilon(soup);
  bvh.leaf_begin.push_back(0);
  bvh.glass.leaf_begin.push_back(0);
  if (hierarchy.nodes.empty()) return bvh;
  const HierarchyNode& root = hierarchy.nodes[0];
  // Padding that holds the exact ray inside every box it enters despite float rounding: the origin
  // and the direction rounded to floats move the ray by at most 2^-24 of the coordinates' and the
  // travelled distance's size, and each slab distance has three roundings. Far above both.
  const glm::dvec3 rlo(root.lo), rhi(root.hi);
  const double magnitude = std::max(glm::length(rlo), glm::length(rhi));
  const double pad = 1e-5 * glm::length(rhi - rlo) + 64.0 * double(std::numeric_limits<float>::epsilon()) * magnitude;
  auto translucent = [&](uint32_t polygon) { return (soup.polygons[polygon].flags & polygon_translucent) != 0; };
  static_cast<ShadowBvhTree&>(bvh) = build_tree(hierarchy, pad, [&](uint32_t p) { return !translucent(p); });
  bvh.glass = build_tree(hierarchy, pad, translucent);
  bvh.casters.reserve(bvh.items.size());
  for (uint32_t item : bvh.items) {
    const Polygon& q = soup.polygons[item];
    ShadowCaster c;
    c.normal = q.normal, c.offset = q.offset, c.id = q.id, c.closed = (q.flags & polygon_closed) != 0;
    const InsideAxes axes = inside_axes(q.normal);
    c.u = uint8_t(axes.u), c.v = uint8_t(axes.v), c.positive = axes.sign > 0.0;
    c.first = uint32_t(bvh.projected.size()), c.count = q.vertex_count;
    for (const Vec3& p : soup.points(q)) bvh.projected.emplace_back(p[c.u], p[c.v]);
    bvh.casters.push_back(c);
  }
  return bvh;
}

size_t ShadowBvh::bytes() const {
  auto tree_bytes = [](const ShadowBvhTree& t) {
    return t.nodes.capacity() * sizeof(ShadowBvhNode) + t.leaf_begin.capacity() * sizeof(uint32_t) +
           t.items.capacity() * sizeof(uint32_t);
  };
  return sizeof(ShadowBvh) + tree_bytes(*this) + tree_bytes(glass) + casters.capacity() * sizeof(ShadowCaster) +
         projected.capacity() * sizeof(glm::dvec2);
}

bool shadow_ray_blocked(const ShadowBvh& bvh, uint32_t self, Vec3 p, const Light& light, ShadowRayMemo* memo,
                        ShadowRayStats* stats) {
  const Segment s = segment_toward(p, light, bvh.ray_epsilon);
  if (s.empty || bvh.nodes.empty()) return false;
  if (stats) ++stats->rays;
  // The memo's polygon is one of the tree's items, so it is a caster exactly when the walk below
  // would find it one: the same own-id exclusion, caster rule and exact test.
  // Moves `blocker` to the memo's front, the others back by one (from slot `from`, or all).
  auto remember = [&](uint32_t blocker, size_t from) {
    for (size_t k = from; k > 0; --k) memo->older[k - 1] = k >= 2 ? memo->older[k - 2] : memo->blocker;
    memo->blocker = blocker;
  };
  if (memo) {
    for (size_t k = 0; k < ShadowRayMemo::size; ++k) {
      const uint32_t blocker = k == 0 ? memo->blocker : memo->older[k - 1];
      if (blocker == UINT32_MAX) break;
      const ShadowCaster& q = bvh.casters[blocker];
      if (stats) ++stats->polygons;
      if (q.id != self && caster_blocks(bvh, q, light, p, s)) {
        if (stats) ++stats->blocked, ++stats->memo_hits;
        if (k > 0) remember(blocker, k);
        return true;
      }
    }
  }
  return walk(bvh, p, s, stats, [&](uint32_t leaf) {
    const uint32_t blocker = leaf_blocker(bvh, leaf, self, p, light, s, stats);
    if (blocker == UINT32_MAX) return false;
    if (memo) remember(blocker, ShadowRayMemo::size - 1);
    if (stats) ++stats->blocked;
    return true;
  });
}

Color shadow_ray_transmittance(const ShadowBvh& bvh, const PolygonSoup& soup, uint32_t self, Vec3 p,
                               const Light& light) {
  const Segment s = segment_toward(p, light, bvh.ray_epsilon);
  if (s.empty || bvh.glass.nodes.empty()) return Color(1.0f);
  glm::dvec3 through(1.0);
  walk(bvh.glass, p, s, nullptr, [&](uint32_t leaf) {
    for (uint32_t i = bvh.glass.leaf_begin[leaf]; i < bvh.glass.leaf_begin[leaf + 1]; ++i) {
      const Polygon& q = soup.polygons[bvh.glass.items[i]];
      if (q.id != self && crosses_pane(soup, q, light, p, s)) through *= pane_transmittance(soup.materials[q.material]);
    }
    return false;
  });
  return Color(through);
}

FixtureMap fixture_map(const PolygonSoup& soup, std::span<const uint32_t> polygons, const Light& light, double margin,
                       int n) {
  FixtureMap map;
  map.light = light.position;
  const Vec3 l = light.position;
  double reach = 0.0;
  std::vector<uint32_t> casters;
  for (uint32_t k : polygons) {
    const Polygon& q = soup.polygons[k];
    if ((q.flags & polygon_translucent) || !casts_shadow(q, light)) continue;
    if (!(std::abs(glm::dot(q.normal, l) - q.offset) > margin)) continue;
    const std::span<const Vec3> v = soup.points(q);
    if (v.size() < 3) continue;
    // Planar and convex, winding about its normal (as intersect_polygon reads it).
    bool usable = true;
    for (size_t m = 0; m < v.size() && usable; ++m) {
      const Vec3 a = v[m], b = v[(m + 1) % v.size()], c = v[(m + 2) % v.size()];
      usable = std::abs(glm::dot(q.normal, a) - q.offset) <= 1e-3 * margin &&
               glm::dot(glm::cross(b - a, c - b), q.normal) > 0.0;
    }
    if (!usable) continue;
    casters.push_back(k);
    for (const Vec3& p : v) reach = std::max(reach, glm::length(p - l));
  }
  if (casters.empty()) return map;
  map.n = n;
  map.far2 = (reach + margin) * (reach + margin);
  map.bits.assign((size_t(6) * size_t(n) * size_t(n) + 63) / 64, 0);
  // Per face, the corner rays' hits of the caster at hand: 1 when inside with the margin.
  std::vector<uint8_t> hit(size_t(n + 1) * size_t(n + 1));
  std::vector<Vec3> inward;  // the caster at hand: per edge, the unit normal into it in its plane
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2, b = axis == 2 ? 0 : axis + 1, c = axis == 0 ? 2 : axis - 1;
    const double sign = face % 2 ? -1.0 : 1.0;
    auto corner = [&](int i, int j) {
      Vec3 d(0.0);
      d[axis] = sign, d[b] = -1.0 + 2.0 * i / n, d[c] = -1.0 + 2.0 * j / n;
      return d;
    };
    for (uint32_t k : casters) {
      const Polygon& q = soup.polygons[k];
      const std::span<const Vec3> v = soup.points(q);
      inward.resize(v.size());
      for (size_t m = 0; m < v.size(); ++m)
        inward[m] = glm::normalize(glm::cross(q.normal, v[(m + 1) % v.size()] - v[m]));
      // The corners to test: those within the caster's image on this face (all its vertices ahead).
      double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
      bool ahead = true;
      for (const Vec3& p : v) {
        const Vec3 d = p - l;
        if (!(d[axis] * sign > 0.0)) ahead = false;
        const double w = d[axis] * sign;
        u0 = std::min(u0, d[b] / w), u1 = std::max(u1, d[b] / w), v0 = std::min(v0, d[c] / w),
        v1 = std::max(v1, d[c] / w);
      }
      if (!ahead) continue;
      const int i0 = std::max(0, int(std::floor((u0 + 1.0) * 0.5 * n))),
                i1 = std::min(n, int(std::ceil((u1 + 1.0) * 0.5 * n)));
      const int j0 = std::max(0, int(std::floor((v0 + 1.0) * 0.5 * n))),
                j1 = std::min(n, int(std::ceil((v1 + 1.0) * 0.5 * n)));
      if (i0 >= i1 || j0 >= j1) continue;
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
          const Vec3 d = corner(i, j);
          const double denom = glm::dot(q.normal, d);
          bool inside = denom != 0.0;
          if (inside) {
            const double t = (q.offset - glm::dot(q.normal, l)) / denom;
            const Vec3 p = l + t * d;
            inside = t > 0.0 && glm::length(p - l) <= reach;
            // At least `margin` inside every edge, in the polygon's plane.
            for (size_t m = 0; m < v.size() && inside; ++m) inside = glm::dot(p - v[m], inward[m]) >= margin;
          }
          hit[size_t(j) * size_t(n + 1) + size_t(i)] = inside;
        }
      }
      for (int j = j0; j < j1; ++j) {
        for (int i = i0; i < i1; ++i) {
          auto at = [&](int x, int y) { return hit[size_t(y) * size_t(n + 1) + size_t(x)] != 0; };
          if (!(at(i, j) && at(i + 1, j) && at(i, j + 1) && at(i + 1, j + 1))) continue;
          const size_t bin = (size_t(face) * size_t(n) + size_t(j)) * size_t(n) + size_t(i);
          map.bits[bin / 64] |= uint64_t(1) << (bin % 64);
        }
      }
    }
  }
  return map;
}

bool shadow_ray_blocked_brute_force(const PolygonSoup& soup, double ray_epsilon, uint32_t self, Vec3 p,
                                    const Light& light) {
  const Segment s = segment_toward(p, light, ray_epsilon);
  if (s.empty) return false;
  for (uint32_t j = 0; j < soup.polygons.size(); ++j) {
    const Polygon& q = soup.polygons[j];
    if (q.id == self || (q.flags & polygon_translucent) || !casts_shadow(q, light)) continue;
    if (intersect_polygon(soup, q, p, s.direction, s.t_min, s.t_max)) return true;
  }
  return false;
}

Color shadow_ray_transmittance_brute_force(const PolygonSoup& soup, double ray_epsilon, uint32_t self, Vec3 p,
                                           const Light& light) {
  const Segment s = segment_toward(p, light, ray_epsilon);
  glm::dvec3 through(1.0);
  if (s.empty) return Color(through);
  for (const Polygon& q : soup.polygons) {
    if (q.id != self && (q.flags & polygon_translucent) && crosses_pane(soup, q, light, p, s))
      through *= pane_transmittance(soup.materials[q.material]);
  }
  return Color(through);
}

}  // namespace rr
