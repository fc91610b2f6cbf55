// Geometric validation behind scene_json (see scene_checks.hpp). Tolerances are relative to the size
// of the thing checked, except the 1e-9 m opening tolerance the format states, so the same shape
// passes or fails wherever it sits within the coordinate limit.
#include "render/scene_io/scene_checks.hpp"

#include "render/scene_io/json_reader.hpp"  // format_number

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace rr {

std::optional<std::pair<size_t, size_t>> find_overlapping_openings(std::span<const Opening> openings) {
  // Sweep in order of offset, remembering the opening that reaches furthest: any overlap shows up as
  // an opening starting before that reach. O(n log n) rather than all pairs.
  std::vector<size_t> order(openings.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return openings[a].offset < openings[b].offset; });
  std::optional<size_t> reach_index;
  double reach = -std::numeric_limits<double>::infinity();
  for (size_t i : order) {
    const Opening& o = openings[i];
    if (reach_index && o.offset < reach - 1e-9) {
      return std::pair{std::min(i, *reach_index), std::max(i, *reach_index)};
    }
    if (o.offset + o.width > reach) {
      reach = o.offset + o.width;
      reach_index = i;
    }
  }
  return std::nullopt;
}

namespace {

double orient(Vec2 a, Vec2 b, Vec2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

// p is collinear with segment ab: does it lie on it?
bool on_segment(Vec2 p, Vec2 a, Vec2 b) {
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

// Closed segments ab and cd share at least one point (crossing, touching or overlapping).
bool segments_meet(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) {
    return true;
  }
  return (o1 == 0 && on_segment(c, a, b)) || (o2 == 0 && on_segment(d, a, b)) || (o3 == 0 && on_segment(a, c, d)) ||
         (o4 == 0 && on_segment(b, c, d));
}

std::string local_problem(std::span<const Vec2> p) {
  size_t n = p.size();
  for (size_t i = 0; i < n; ++i) {
    if (p[i] == p[(i + 1) % n]) {
      return "point " + std::to_string((i + 1) % n) + " repeats point " + std::to_string(i);
    }
  }
  for (size_t i = 0; i < n; ++i) {
    Vec2 prev = p[(i + n - 1) % n], here = p[i], next = p[(i + 1) % n];
    if (orient(prev, here, next) == 0 && glm::dot(prev - here, next - here) > 0) {
      return "the edges meeting at point " + std::to_string(i) + " fold back onto each other";
    }
  }
  return "";
}

// Non-adjacent edges that meet. Edges are visited in order of their minimum x and only compared
// while their x ranges overlap, which keeps ordinary footprints near-linear.
std::string crossing_problem(std::span<const Vec2> p) {
  size_t n = p.size();
  struct Span {
    size_t edge;
    double min_x, max_x;
  };
  std::vector<Span> spans(n);
  for (size_t i = 0; i < n; ++i) {
    Vec2 a = p[i], b = p[(i + 1) % n];
    spans[i] = {i, std::min(a.x, b.x), std::max(a.x, b.x)};
  }
  std::sort(spans.begin(), spans.end(),
            [](const Span& s, const Span& t) { return s.min_x < t.min_x || (s.min_x == t.min_x && s.edge < t.edge); });
  for (size_t a = 0; a < n; ++a) {
    for (size_t b = a + 1; b < n && spans[b].min_x <= spans[a].max_x; ++b) {
      size_t i = std::min(spans[a].edge, spans[b].edge), j = std::max(spans[a].edge, spans[b].edge);
      if (j == i + 1 || (i == 0 && j == n - 1)) continue;  // neighbours share a point by design
      if (segments_meet(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n])) {
        return "the edges starting at points " + std::to_string(i) + " and " + std::to_string(j) + " intersect";
      }
    }
  }
  return "";
}

}  // namespace

std::string simple_polygon_problem(std::span<const Vec2> points) {
  if (points.size() < 3) return "it has fewer than 3 points";
  if (std::string problem = local_problem(points); !problem.empty()) return problem;
  // Crossings first: a bow tie also has zero area, but "edges intersect" is the useful message.
  if (std::string problem = crossing_problem(points); !problem.empty()) return problem;
  Vec2 lo = points[0], hi = points[0];
  double twice_area = 0.0;
  for (size_t i = 0; i < points.size(); ++i) {
    lo = glm::min(lo, points[i]);
    hi = glm::max(hi, points[i]);
    twice_area += orient(points[0], points[i], points[(i + 1) % points.size()]);
  }
  // Same relative threshold as mesh faces: an area below that of a square 1e-8 of the size.
  double size = glm::length(hi - lo);
  if (!(std::abs(twice_area) > 2.0 * (1e-8 * size) * (1e-8 * size))) return "it has zero area";
  return "";
}

std::optional<size_t> find_repeated_index(std::span<const uint32_t> face) {
  if (face.size() <= 16) {  // typical faces: no allocation
    for (size_t k = 1; k < face.size(); ++k) {
      if (std::find(face.begin(), face.begin() + ptrdiff_t(k), face[k]) != face.begin() + ptrdiff_t(k)) {
        return k;
      }
    }
    return std::nullopt;
  }
  std::vector<std::pair<uint32_t, size_t>> sorted(face.size());
  for (size_t k = 0; k < face.size(); ++k) sorted[k] = {face[k], k};
  std::sort(sorted.begin(), sorted.end());
  for (size_t k = 1; k < sorted.size(); ++k) {
    if (sorted[k].first == sorted[k - 1].first) return sorted[k].second;
  }
  return std::nullopt;
}

std::optional<BadFace> find_bad_mesh_face(std::span<const Vec3> vertices,
                                          std::span<const std::vector<uint32_t>> faces) {
  if (faces.empty()) return std::nullopt;  // otherwise, indices being in range, vertices exist
  Vec3 lo = vertices[0], hi = vertices[0];
  for (Vec3 v : vertices) {
    lo = glm::min(lo, v);
    hi = glm::max(hi, v);
  }
  double size = glm::length(hi - lo);
  double plane_tolerance = 1e-6 * size;
  for (size_t f = 0; f < faces.size(); ++f) {
    const std::vector<uint32_t>& face = faces[f];
    Vec3 centroid{0.0};
    for (uint32_t index : face) centroid += vertices[index];
    centroid /= double(face.size());
    Vec3 normal{0.0};  // Newell: twice the vector area, robust for non-convex faces
    for (size_t k = 0; k < face.size(); ++k) {
      normal += glm::cross(vertices[face[k]] - centroid, vertices[face[(k + 1) % face.size()]] - centroid);
    }
    double twice_area = glm::length(normal);
    // An area below that of a square 1e-8 of the mesh size is rounding noise, not a face.
    if (!(twice_area > 2.0 * (1e-8 * size) * (1e-8 * size))) return BadFace{f, "face has zero area"};
    normal /= twice_area;
    for (size_t k = 0; k < face.size(); ++k) {
      double distance = std::abs(glm::dot(normal, vertices[face[k]] - centroid));
      if (distance > plane_tolerance) {
        return BadFace{f, "face is not planar: its vertex " + std::to_string(k) + " lies " + format_number(distance) +
                              " m off its plane (tolerance " + format_number(plane_tolerance) +
                              " m, 1e-6 of the mesh size)"};
      }
    }
  }
  return std::nullopt;
}

}  // namespace rr
