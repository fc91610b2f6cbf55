// Placement checks (see placement.hpp). Walls and solids become plan footprints (convex hull of their
// tessellated vertices, plus a height range); pairs whose bounding boxes overlap are found by a sweep
// along x and tested with separating axes. An overlap must exceed the tolerance on every axis and in
// height to count, so elements that merely touch are quiet.
#include "render/core/placement.hpp"

#include <algorithm>
#include <limits>
#include <optional>
#include <utility>

namespace rr {

namespace {

struct Footprint {
  ElementRef element;           // a wall or a solid
  std::vector<Vec2> hull = {};  // counter-clockwise in (x, z); fewer than 3 points: no area in plan
  Vec2 lo{std::numeric_limits<double>::max()}, hi{std::numeric_limits<double>::lowest()};
  double y0 = std::numeric_limits<double>::max(), y1 = std::numeric_limits<double>::lowest();
};

double cross(Vec2 o, Vec2 a, Vec2 b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

// Andrew's monotone chain; drops duplicate and collinear points.
std::vector<Vec2> convex_hull(std::vector<Vec2> points) {
  std::sort(points.begin(), points.end(), [](Vec2 a, Vec2 b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  std::vector<Vec2> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);  // the last point repeats the first
  return hull;
}

bool is_wall(const Footprint& f) { return f.element.kind == ElementKind::wall; }

std::vector<Footprint> make_footprints(const PolygonSoup& soup) {
  std::vector<Footprint> out;
  std::vector<std::optional<size_t>> slot(soup.objects.size());  // object -> footprint
  for (size_t o = 0; o < soup.objects.size(); ++o) {
    const ElementRef element = soup.objects[o].element;
    if (element.kind == ElementKind::wall || element.kind == ElementKind::solid) {
      slot[o] = out.size();
      out.push_back(Footprint{element});
    }
  }
  std::vector<std::vector<Vec2>> points(out.size());
  for (const Polygon& polygon : soup.polygons) {
    if (!slot[polygon.object]) continue;
    Footprint& f = out[*slot[polygon.object]];
    for (const Vec3& p : soup.points(polygon)) {
      points[*slot[polygon.object]].push_back({p.x, p.z});
      f.y0 = std::min(f.y0, p.y);
      f.y1 = std::max(f.y1, p.y);
    }
  }
  for (size_t i = 0; i < out.size(); ++i) {
    out[i].hull = convex_hull(std::move(points[i]));
    for (Vec2 p : out[i].hull) {
      out[i].lo = glm::min(out[i].lo, p);
      out[i].hi = glm::max(out[i].hi, p);
    }
  }
  return out;
}

// The smallest overlap of the two hulls' projections over every edge normal of both (the plan
// penetration depth); stops early once it is at most `tolerance`. Counts projections into `work`.
double plan_penetration(const std::vector<Vec2>& a, const std::vector<Vec2>& b, double tolerance, size_t& work) {
  double depth = std::numeric_limits<double>::max();
  auto extent = [](const std::vector<Vec2>& hull, Vec2 axis) {
    double lo = std::numeric_limits<double>::max(), hi = std::numeric_limits<double>::lowest();
    for (Vec2 p : hull) {
      double d = glm::dot(p, axis);
      lo = std::min(lo, d);
      hi = std::max(hi, d);
    }
    return std::pair{lo, hi};
  };
  for (const std::vector<Vec2>* hull : {&a, &b}) {
    for (size_t i = 0; i < hull->size() && depth > tolerance; ++i) {
      Vec2 edge = (*hull)[(i + 1) % hull->size()] - (*hull)[i];
      double length = glm::length(edge);
      if (length == 0.0) continue;
      Vec2 axis{-edge.y / length, edge.x / length};
      auto [a_lo, a_hi] = extent(a, axis);
      auto [b_lo, b_hi] = extent(b, axis);
      work += a.size() + b.size();
      depth = std::min(depth, std::min(a_hi, b_hi) - std::max(a_lo, b_lo));
    }
  }
  return depth;
}

class WarningList {
 public:
  explicit WarningList(size_t max) : max_(max) {}
  void add(const PlacementWarning& warning) {
    if (items_.size() < max_) {
      items_.push_back(warning);
    } else {
      ++suppressed_;
    }
  }
  std::vector<PlacementWarning> finish(bool stopped_early) {
    if (suppressed_ > 0 || stopped_early) {
      const PlacementIssue issue = stopped_early ? PlacementIssue::stopped_early : PlacementIssue::more_problems;
      items_.push_back({issue, ElementRef{}, ElementRef{}, 0.0, 0.0, suppressed_});
    }
    return std::move(items_);
  }

 private:
  size_t max_;
  size_t suppressed_ = 0;
  std::vector<PlacementWarning> items_;
};

void check_openings(const Scene& scene, const PlacementLimits& limits, WarningList& out) {
  const double clearance = limits.opening_clearance_m;
  for (size_t w = 0; w < scene.geometry.walls.size(); ++w) {
    const Wall& wall = scene.geometry.walls[w];
    const double length = glm::length(wall.end - wall.start);
    std::vector<size_t> order(wall.openings.size());
    for (size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return wall.openings[a].offset < wall.openings[b].offset; });
    for (size_t n = 0; n < order.size(); ++n) {
      const Opening& o = wall.openings[order[n]];
      const ElementRef opening = ElementRef::opening_of(w, order[n]);
      if (o.offset < clearance) {
        out.add({PlacementIssue::opening_near_start, opening, {}, o.offset, clearance, 0});
      }
      if (double rest = length - (o.offset + o.width); rest < clearance) {
        out.add({PlacementIssue::opening_near_end, opening, {}, std::max(rest, 0.0), clearance, 0});
      }
      if (n > 0) {
        const Opening& previous = wall.openings[order[n - 1]];
        if (double gap = o.offset - (previous.offset + previous.width); gap < clearance) {
          out.add({PlacementIssue::openings_too_close, opening, ElementRef::opening_of(w, order[n - 1]),
                   std::max(gap, 0.0), clearance, 0});
        }
      }
    }
  }
}

void check_floor(const Scene& scene, const std::vector<Footprint>& footprints, const PlacementLimits& limits,
                 WarningList& out) {
  if (!scene.geometry.has_floor) return;
  const Floor& floor = scene.geometry.floor;
  const Vec2 lo = floor.origin;
  const Vec2 hi = floor.origin + Vec2(floor.cells_x, floor.cells_z) * floor.cell_size;
  for (const Footprint& f : footprints) {
    if (is_wall(f) || f.hull.empty()) continue;
    double beyond = std::max({lo.x - f.lo.x, lo.y - f.lo.y, f.hi.x - hi.x, f.hi.y - hi.y});
    if (beyond > limits.tolerance_m) {
      out.add({PlacementIssue::beyond_floor, f.element, {}, beyond, 0.0, 0});
    }
  }
}

// Returns false when the pair work ran out before every pair was tested.
bool check_intersections(const std::vector<Footprint>& footprints, const PlacementLimits& limits, WarningList& out) {
  const double tol = limits.tolerance_m;
  std::vector<size_t> order;
  for (size_t i = 0; i < footprints.size(); ++i) {
    if (footprints[i].hull.size() >= 3) order.push_back(i);
  }
  // Sweep along x; ties by index keep the output deterministic.
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return footprints[a].lo.x < footprints[b].lo.x || (footprints[a].lo.x == footprints[b].lo.x && a < b);
  });
  std::vector<std::pair<size_t, size_t>> hits;  // (earlier, later) in element order
  size_t work = 0;
  for (size_t n = 0; n < order.size(); ++n) {
    const Footprint& a = footprints[order[n]];
    for (size_t m = n + 1; m < order.size() && footprints[order[m]].lo.x < a.hi.x - tol; ++m) {
      const Footprint& b = footprints[order[m]];
      if (is_wall(a) && is_wall(b)) continue;  // walls meet at joins by design
      if (b.lo.y >= a.hi.y - tol || a.lo.y >= b.hi.y - tol) continue;
      if (std::min(a.y1, b.y1) - std::max(a.y0, b.y0) <= tol) continue;
      if (work > limits.max_pair_work) return false;
      if (plan_penetration(a.hull, b.hull, tol, work) > tol) {
        hits.push_back(std::minmax(order[n], order[m]));
      }
    }
  }
  std::sort(hits.begin(), hits.end(),
            [](auto x, auto y) { return std::pair(x.second, x.first) < std::pair(y.second, y.first); });
  for (auto [first, second] : hits) {
    const Footprint& a = footprints[first];
    const Footprint& b = footprints[second];
    // Walls come before solids in element order, so the later element of a pair is always a solid.
    out.add({PlacementIssue::intersects, b.element, a.element, 0.0, 0.0, 0});
  }
  return true;
}

}  // namespace

std::vector<PlacementWarning> placement_warnings(const Scene& scene, const PolygonSoup& soup,
                                                 const PlacementLimits& limits) {
  WarningList out(limits.max_warnings);
  check_openings(scene, limits, out);
  std::vector<Footprint> footprints = make_footprints(soup);
  check_floor(scene, footprints, limits, out);
  bool complete = check_intersections(footprints, limits, out);
  return out.finish(!complete);
}

}  // namespace rr
