// Placement checks (see placement.hpp). Walls and solids become plan footprints (convex hull of their
// tessellated vertices, plus a height range); pairs whose bounding boxes overlap are found by a sweep
// along x and tested with separating axes. An overlap must exceed the tolerance on every axis and in
// height to count, so elements that merely touch are quiet. A pair with a piece of furniture in it
// whose hulls overlap is then tested polygon against polygon (surface_contact.hpp): it warns when
// some faces of the two cross, or when a face of the piece lies inside the other element, closed and
// convex; so a chair tucked under a table (hulls overlapping, no face through another) is quiet.
// Pairs without a piece keep the hull test: their solids are closed, and two boxes overlapping with
// flush sides cross no face.
#include "render/core/placement.hpp"

#include "render/core/surface_contact.hpp"

#include <algorithm>
#include <limits>
#include <optional>
#include <utility>

namespace rr {

namespace {

struct Footprint {
  ElementRef element;           // a wall or a solid
  bool closed = false;          // its faces bound a volume (SceneObject::closed)
  bool piece = false;           // a piece of furniture: a model's parts, which need not bound a volume
  std::vector<Vec2> hull = {};  // counter-clockwise in (x, z); fewer than 3 points: no area in plan
  Vec2 lo{std::numeric_limits<double>::max()}, hi{std::numeric_limits<double>::lowest()};
  double y0 = std::numeric_limits<double>::max(), y1 = std::numeric_limits<double>::lowest();
  std::vector<uint32_t> polygons = {};  // its polygons in the soup
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

// A face of `inner` lies inside `outer`, which is closed: the middle of one of its polygons is behind
// every plane of outer's polygons by more than `tol`. Exact for a convex `outer` (boxes, cylinders,
// pyramids); a concave one (an L-shaped prism, a wall with openings) may hold a piece unnoticed.
bool holds(const PolygonSoup& soup, const Footprint& outer, const Footprint& inner, double tol, size_t& work) {
  if (!outer.closed || outer.polygons.empty()) return false;
  for (uint32_t i : inner.polygons) {
    Vec3 middle{0.0};
    const std::span<const Vec3> points = soup.points(soup.polygons[i]);
    for (const Vec3& q : points) middle += q;
    middle /= double(points.size());
    work += outer.polygons.size();
    const bool inside = std::all_of(outer.polygons.begin(), outer.polygons.end(), [&](uint32_t o) {
      const Polygon& face = soup.polygons[o];
      return glm::dot(face.normal, middle) - face.offset < -tol;
    });
    if (inside) return true;
  }
  return false;
}

std::vector<Footprint> make_footprints(const Scene& scene, const PolygonSoup& soup) {
  std::vector<Footprint> out;
  std::vector<std::optional<size_t>> slot(soup.objects.size());  // object -> footprint
  for (size_t o = 0; o < soup.objects.size(); ++o) {
    const ElementRef element = soup.objects[o].element;
    if (element.kind == ElementKind::wall || element.kind == ElementKind::solid) {
      slot[o] = out.size();
      const bool piece =
          element.kind == ElementKind::solid && scene.geometry.solids[element.index].type == SolidType::piece;
      out.push_back(Footprint{element, soup.objects[o].closed, piece});
    }
  }
  std::vector<std::vector<Vec2>> points(out.size());
  for (uint32_t i = 0; i < soup.polygons.size(); ++i) {
    const Polygon& polygon = soup.polygons[i];
    if (!slot[polygon.object]) continue;
    Footprint& f = out[*slot[polygon.object]];
    f.polygons.push_back(i);
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

// Every problem found, then the deepest `max` of them in order (ties keep the order found, which is
// element order) and one warning counting the rest.
class WarningList {
 public:
  explicit WarningList(size_t max) : max_(max) {}
  void add(const PlacementWarning& warning) { items_.push_back(warning); }
  std::vector<PlacementWarning> finish(bool stopped_early) {
    std::stable_sort(items_.begin(), items_.end(),
                     [](const PlacementWarning& a, const PlacementWarning& b) { return a.depth_m > b.depth_m; });
    const size_t suppressed = items_.size() > max_ ? items_.size() - max_ : 0;
    items_.resize(items_.size() - suppressed);
    if (suppressed > 0 || stopped_early) {
      const PlacementIssue issue = stopped_early ? PlacementIssue::stopped_early : PlacementIssue::more_problems;
      items_.push_back({issue, ElementRef{}, ElementRef{}, 0.0, 0.0, suppressed});
    }
    return std::move(items_);
  }

 private:
  size_t max_;
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
        out.add({PlacementIssue::opening_near_start, opening, {}, o.offset, clearance, 0, clearance - o.offset});
      }
      if (double rest = std::max(length - (o.offset + o.width), 0.0); rest < clearance) {
        out.add({PlacementIssue::opening_near_end, opening, {}, rest, clearance, 0, clearance - rest});
      }
      if (n > 0) {
        const Opening& previous = wall.openings[order[n - 1]];
        if (double gap = std::max(o.offset - (previous.offset + previous.width), 0.0); gap < clearance) {
          out.add({PlacementIssue::openings_too_close, opening, ElementRef::opening_of(w, order[n - 1]), gap, clearance,
                   0, clearance - gap});
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
      out.add({PlacementIssue::beyond_floor, f.element, {}, beyond, 0.0, 0, beyond});
    }
  }
}

// Returns false when the pair work ran out before every pair was tested.
bool check_intersections(const std::vector<Footprint>& footprints, const PolygonSoup& soup,
                         const PlacementLimits& limits, WarningList& out) {
  const double tol = limits.tolerance_m;
  std::vector<size_t> order;
  for (size_t i = 0; i < footprints.size(); ++i) {
    if (footprints[i].hull.size() >= 3) order.push_back(i);
  }
  // Sweep along x; ties by index keep the output deterministic.
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return footprints[a].lo.x < footprints[b].lo.x || (footprints[a].lo.x == footprints[b].lo.x && a < b);
  });
  struct Hit {
    size_t first, second;  // earlier, later in element order
    double depth;          // the smaller of the plan penetration and the overlap in height
  };
  std::vector<Hit> hits;
  size_t work = 0;
  for (size_t n = 0; n < order.size(); ++n) {
    const Footprint& a = footprints[order[n]];
    for (size_t m = n + 1; m < order.size() && footprints[order[m]].lo.x < a.hi.x - tol; ++m) {
      const Footprint& b = footprints[order[m]];
      if (is_wall(a) && is_wall(b)) continue;  // walls meet at joins by design
      if (b.lo.y >= a.hi.y - tol || a.lo.y >= b.hi.y - tol) continue;
      const double height_overlap = std::min(a.y1, b.y1) - std::max(a.y0, b.y0);
      if (height_overlap <= tol) continue;
      if (work > limits.max_pair_work) return false;
      const double depth = plan_penetration(a.hull, b.hull, tol, work);
      if (depth <= tol) continue;
      if (a.piece || b.piece) {
        const ContactResult contact = surfaces_cross(soup, a.polygons, b.polygons, tol, work, limits.max_pair_work);
        if (contact == ContactResult::out_of_work) return false;
        if (contact == ContactResult::apart && !holds(soup, a, b, tol, work) && !holds(soup, b, a, tol, work)) continue;
      }
      auto [first, second] = std::minmax(order[n], order[m]);
      hits.push_back({first, second, std::min(depth, height_overlap)});
    }
  }
  std::sort(hits.begin(), hits.end(),
            [](const Hit& x, const Hit& y) { return std::pair(x.second, x.first) < std::pair(y.second, y.first); });
  for (const Hit& hit : hits) {
    const Footprint& a = footprints[hit.first];
    const Footprint& b = footprints[hit.second];
    // Walls come before solids in element order, so the later element of a pair is always a solid.
    out.add({PlacementIssue::intersects, b.element, a.element, 0.0, 0.0, 0, hit.depth});
  }
  return true;
}

}  // namespace

std::vector<PlacementWarning> placement_warnings(const Scene& scene, const PolygonSoup& soup,
                                                 const PlacementLimits& limits) {
  WarningList out(limits.max_warnings);
  check_openings(scene, limits, out);
  std::vector<Footprint> footprints = make_footprints(scene, soup);
  check_floor(scene, footprints, limits, out);
  bool complete = check_intersections(footprints, soup, limits, out);
  return out.finish(!complete);
}

size_t placement_problem_count(const std::vector<PlacementWarning>& warnings) {
  size_t count = 0;
  for (const PlacementWarning& w : warnings) {
    const bool summary = w.issue == PlacementIssue::more_problems || w.issue == PlacementIssue::stopped_early;
    count += summary ? w.count : 1;
  }
  return count;
}

}  // namespace rr
