// The painter's `newell` key: the Newell-Newell-Sancha refinement of a back-to-front list
// (docs/painter.md).
//
// The list starts in mean-depth order. Its head P is drawn only when no polygon Q still in the list
// could be hidden by it, i.e. when for every Q whose screen box shares a grid cell with P's one of
// these holds, tried in this order:
//   1. depth extents: P is entirely farther than Q;
//   2. screen x extents, 3. screen y extents do not overlap;
//   4. P lies entirely behind Q's plane (on the side away from the eye);
//   5. Q lies entirely in front of P's plane (on the eye's side);
//   6. the projections of the visible parts of P and Q do not overlap (separating axes).
// Otherwise Q must be drawn (at least partly) before P. If Q can be (Q entirely farther than P, Q
// entirely behind P's plane, or P entirely in front of Q's plane) and Q has not been moved before,
// Q moves to the head of the list and is marked. Otherwise the pair has no order of whole polygons:
// P and Q pierce each other, or Q is marked, i.e. it already went ahead once and the list is cycling.
// Then one polygon is cut by the other's plane (split_polygon) and the pieces are placed so that the
// pair's conflict is gone: [far part, other, near part]. When neither plane cuts the other polygon
// (a cycle of polygons that each lie on one side of the others' planes), the marked polygon is cut in
// half across its longest edge instead. Marks are cleared after every split (the pieces start over).
//
// Termination: every step emits a polygon, marks one, or splits one. Splits are limited to
// newell_max_splits(n); candidate visits (every grid entry looked at, depth test included) to
// newell_max_checks(n). Past the split bound a conflict that needs a split draws the head as it
// stands; past the check bound the rest of the list is drawn in its current order. Either way every
// visible polygon is still drawn exactly once, and PainterOrder::budget_exhausted says it happened.
//
// Cost: candidate pairs come from a uniform grid over the viewport with cells about half the median
// polygon's size on screen, so only pairs whose screen boxes share a cell are looked at. Grid entries
// carry the polygon's farthest depth, so the depth test of most pairs touches nothing else, and cell
// lists drop polygons already drawn once they are mostly such. A per-polygon cursor resumes P's scan
// where it stopped, so pairs already shown safe are not looked at again when P comes back to the head.
#include "render/pipelines/painter_detail.hpp"

#include "render/core/polygon_ops.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

namespace rr::painter_detail {

double newell_epsilon(const PolygonSoup& soup) {
  if (soup.positions.empty()) return 0.0;
  Vec3 lo = soup.positions[0], hi = lo;
  for (const Vec3& p : soup.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  double diagonal = glm::length(hi - lo);
  double magnitude =
      std::max({std::abs(lo.x), std::abs(lo.y), std::abs(lo.z), std::abs(hi.x), std::abs(hi.y), std::abs(hi.z)});
  // A plane distance dot(n, p) - offset carries a few ulps of |p|: stay well above that.
  return std::max(newell_epsilon_fraction * diagonal, 64.0 * DBL_EPSILON * magnitude);
}

namespace {

constexpr int32_t none = -1;
constexpr double overlap_tolerance_px = 1e-7;  // projections closer than this count as touching

struct Cursor {
  bool started = false;
  uint32_t base = 0;             // items below this index are found through the grid
  uint32_t cell = 0;             // position in the polygon's own cell range (row-major)
  uint32_t entry = 0;            // position in that cell's list
  uint32_t cell_generation = 0;  // of that cell's list when `entry` was taken
  uint32_t seen = 0;             // items in [base, seen) were checked directly
};

struct GridEntry {
  uint32_t item;
  uint32_t plane_group;  // the item's Polygon::plane_group (in what would be padding)
  double dmax;           // the item's farthest view depth, for the depth-extent test
};

struct CellRange {
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // inclusive
};

// Min and max of (eye side) * signed distance of a polygon's vertices to a plane: > 0 on the eye's side.
struct SideRange {
  double lo = 0.0, hi = 0.0;
};

class Newell {
 public:
  Newell(const FrameInput& input, ItemBuilder& builder, std::vector<SortItem>& items, PainterOrder& order)
      : input_(input), builder_(builder), items_(items), order_(order) {
    eps_ = newell_epsilon(input.soup);
    const size_t n = items.size();
    max_splits_ = newell_max_splits(n);
    max_checks_ = newell_max_checks(n);
    const double w = input.view.width, h = input.view.height;
    // Square cells half the median polygon's size (the larger side of its screen box), which needed
    // the fewest candidate visits on the benchmark's tube grids; no more than ~4 cells per polygon.
    std::vector<double> sizes;
    sizes.reserve(n);
    for (const SortItem& it : items) sizes.push_back(std::max(it.x1 - it.x0, it.y1 - it.y0));
    double cell = std::max(w, h);
    if (n) {
      std::nth_element(sizes.begin(), sizes.begin() + ptrdiff_t(n / 2), sizes.end());
      cell = sizes[n / 2] * 0.5;
    }
    cell = std::clamp(std::max(cell, std::sqrt(w * h / (4.0 * double(std::max<size_t>(n, 1))))), 1.0, std::max(w, h));
    nx_ = std::clamp(int(std::ceil(w / cell)), 1, 1024);
    ny_ = std::clamp(int(std::ceil(h / cell)), 1, 1024);
    cell_w_ = w / nx_;
    cell_h_ = h / ny_;
    grid_.resize(size_t(nx_) * size_t(ny_));
    grid_dead_.resize(grid_.size(), 0);
    grid_generation_.resize(grid_.size(), 0);
    for (uint32_t i = 0; i < n; ++i) register_item(i);
    // The initial list: the given order.
    for (uint32_t i = 0; i < n; ++i) {
      prev_[i] = int32_t(i) - 1;
      next_[i] = i + 1 < n ? int32_t(i + 1) : none;
    }
    head_ = n ? 0 : none;
  }

  void run() {
    size_t steps = 0;
    while (head_ != none) {
      if ((++steps & 1023) == 0) check_cancel(input_.context.cancel);
      if (checks_ > max_checks_) {  // work bound: draw the rest as it stands
        order_.budget_exhausted = true;
        while (head_ != none) emit(uint32_t(head_));
        break;
      }
      const uint32_t p = uint32_t(head_);
      const int32_t found = find_conflict(p);
      if (found == none) {
        emit(p);
        continue;
      }
      const uint32_t q = uint32_t(found);
      const bool q_may_go_first = same_plane(p, q) || items_[q].dmin >= items_[p].dmax - eps_ ||
                                  side_range(q, p).hi <= eps_ || side_range(p, q).lo >= -eps_;
      if (q_may_go_first && mark_[q] != epoch_) {
        mark_[q] = epoch_;
        unlink(q);
        push_front(q);
        continue;
      }
      if (order_.splits >= max_splits_) {  // split bound: the classic painter's answer
        order_.budget_exhausted = true;
        emit(p);
        continue;
      }
      if (!resolve(p, q, q_may_go_first)) emit(p);  // nothing can be cut (degenerate): draw as is
    }
  }

 private:
  // --- items -----------------------------------------------------------------------------------

  const PolygonSoup& soup_of(uint32_t i) const { return items_[i].fragment ? order_.fragments : input_.soup; }
  const Polygon& polygon_of(uint32_t i) const { return soup_of(i).polygons[items_[i].index]; }

  int eye_side(const Polygon& poly) const {
    double d = plane_of(poly).distance(input_.view.eye);
    return d > eps_ ? 1 : (d < -eps_ ? -1 : 0);
  }

  void register_item(uint32_t i) {
    const SortItem& it = items_[i];
    CellRange r{cell_x(it.x0), cell_y(it.y0), cell_x(it.x1), cell_y(it.y1)};
    cells_.push_back(r);
    side_.push_back(int8_t(eye_side(polygon_of(i))));
    prev_.push_back(none);
    next_.push_back(none);
    alive_.push_back(1);
    mark_.push_back(0);
    cursor_.push_back({});
    const uint32_t group = polygon_of(i).plane_group;
    for (int y = r.y0; y <= r.y1; ++y) {
      for (int x = r.x0; x <= r.x1; ++x) grid_[size_t(y) * size_t(nx_) + size_t(x)].push_back({i, group, it.dmax});
    }
  }

  int cell_x(double x) const { return std::clamp(int(x / cell_w_), 0, nx_ - 1); }
  int cell_y(double y) const { return std::clamp(int(y / cell_h_), 0, ny_ - 1); }

  // --- the list ----------------------------------------------------------------------------------

  void unlink(uint32_t i) {
    if (prev_[i] != none) next_[size_t(prev_[i])] = next_[i];
    else if (head_ == int32_t(i)) head_ = next_[i];
    if (next_[i] != none) prev_[size_t(next_[i])] = prev_[i];
    prev_[i] = next_[i] = none;
  }

  void push_front(uint32_t i) {
    prev_[i] = none;
    next_[i] = head_;
    if (head_ != none) prev_[size_t(head_)] = int32_t(i);
    head_ = int32_t(i);
  }

  bool linked(uint32_t i) const { return head_ == int32_t(i) || prev_[i] != none; }

  // Puts `sequence` (item indices, `none` skipped) at the head of the list, in that order.
  void place_front(std::initializer_list<int32_t> sequence) {
    std::vector<int32_t> seq(sequence);
    for (int32_t i : seq) {
      if (i != none && linked(uint32_t(i))) unlink(uint32_t(i));
    }
    for (auto it = seq.rbegin(); it != seq.rend(); ++it) {
      if (*it != none) push_front(uint32_t(*it));
    }
  }

  void emit(uint32_t i) {
    unlink(i);
    retire(i);
    order_.items.push_back({items_[i].index, items_[i].fragment});
  }

  // Marks an item gone (drawn or split) and drops dead entries from cell lists that are mostly dead,
  // keeping their order; cursors in a compacted list restart it (grid_generation_).
  void retire(uint32_t i) {
    alive_[i] = 0;
    const CellRange r = cells_[i];
    for (int y = r.y0; y <= r.y1; ++y) {
      for (int x = r.x0; x <= r.x1; ++x) {
        const size_t cell = size_t(y) * size_t(nx_) + size_t(x);
        std::vector<GridEntry>& list = grid_[cell];
        if (++grid_dead_[cell] * 2 <= list.size() || list.size() < 16) continue;
        std::erase_if(list, [&](const GridEntry& e) { return !alive_[e.item]; });
        grid_dead_[cell] = 0;
        ++grid_generation_[cell];
      }
    }
  }

  // --- the tests ---------------------------------------------------------------------------------

  // Vertices of item `a` against the plane of item `b`, signed so that the eye's side is positive.
  SideRange side_range(uint32_t a, uint32_t b) const {
    const int s = side_[b];
    if (s == 0) return {};  // b is seen edge-on: every side test holds
    const Plane plane = plane_of(polygon_of(b));
    SideRange r{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
    for (const Vec3& v : soup_of(a).points(polygon_of(a))) {
      double d = s * plane.distance(v);
      r.lo = std::min(r.lo, d), r.hi = std::max(r.hi, d);
    }
    return r;
  }

  // Separating-axis test on the visible parts of two convex polygons on screen.
  bool projections_overlap(uint32_t a, uint32_t b) const {
    const Vec2* pa = builder_.screen.data() + items_[a].screen_first;
    const Vec2* pb = builder_.screen.data() + items_[b].screen_first;
    const uint32_t na = items_[a].screen_count, nb = items_[b].screen_count;
    auto separated_by_edges = [&](const Vec2* p, uint32_t n) {
      for (uint32_t k = 0; k < n; ++k) {
        Vec2 e = p[(k + 1) % n] - p[k];
        Vec2 axis(-e.y, e.x);
        double len = glm::length(axis);
        if (!(len > 0.0)) continue;
        double amin = std::numeric_limits<double>::infinity(), amax = -amin, bmin = amin, bmax = -amin;
        for (uint32_t i = 0; i < na; ++i) {
          double t = glm::dot(axis, pa[i]);
          amin = std::min(amin, t), amax = std::max(amax, t);
        }
        for (uint32_t i = 0; i < nb; ++i) {
          double t = glm::dot(axis, pb[i]);
          bmin = std::min(bmin, t), bmax = std::max(bmax, t);
        }
        double tol = overlap_tolerance_px * len;
        if (amax <= bmin + tol || bmax <= amin + tol) return true;
      }
      return false;
    };
    return !separated_by_edges(pa, na) && !separated_by_edges(pb, nb);
  }

  // One plane group (Polygon::plane_group): where the two overlap the lower id must show, so it is
  // drawn last, whatever the depths of the two triangulations of one plane say.
  bool same_plane(uint32_t p, uint32_t q) const {
    const uint32_t group = polygon_of(p).plane_group;
    return group != 0 && group == polygon_of(q).plane_group;
  }

  // True when P may be drawn before Q: nothing of Q that P overlaps on screen lies behind P.
  bool may_draw_before(uint32_t p, uint32_t q) {
    const SortItem& P = items_[p];
    const SortItem& Q = items_[q];
    const bool coplanar = same_plane(p, q);
    if (!coplanar && P.dmin >= Q.dmax - eps_) return true;  // 1. P entirely farther
    ++order_.pairs_tested;
    if (P.x1 <= Q.x0 || Q.x1 <= P.x0) return true;  // 2. x extents
    if (P.y1 <= Q.y0 || Q.y1 <= P.y0) return true;  // 3. y extents
    if (coplanar) return polygon_of(p).id >= polygon_of(q).id || !projections_overlap(p, q);
    if (side_range(p, q).hi <= eps_) return true;   // 4. P behind Q's plane
    if (side_range(q, p).lo >= -eps_) return true;  // 5. Q in front of P's plane
    return !projections_overlap(p, q);              // 6. projections
  }

  // The first item still in the list that P may hide, or `none`. Resumes where P's last scan
  // stopped: pairs already shown safe stay safe (geometry does not change; pieces are new items).
  // One pair test: counted against the work bound, and the deadline checked every 16k of them, since
  // one search can scan a long cell list (the cursor keeps its place, but a cancel ends the sort).
  void count_check() {
    if ((++checks_ & 16383) == 0) check_cancel(input_.context.cancel);
  }

  int32_t find_conflict(uint32_t p) {
    Cursor& c = cursor_[p];
    if (!c.started) {
      c.started = true;
      c.base = uint32_t(items_.size());
      c.seen = c.base;
    }
    const CellRange r = cells_[p];
    const double near_limit = items_[p].dmin + eps_;  // Q farthest below this: 1. P entirely farther
    const uint32_t group = polygon_of(p).plane_group;
    const uint32_t width = uint32_t(r.x1 - r.x0 + 1), count = width * uint32_t(r.y1 - r.y0 + 1);
    for (; c.cell < count; ++c.cell, c.entry = 0) {
      const int cx = r.x0 + int(c.cell % width), cy = r.y0 + int(c.cell / width);
      const size_t cell = size_t(cy) * size_t(nx_) + size_t(cx);
      if (c.cell_generation != grid_generation_[cell]) c.entry = 0;  // compacted since: restart it
      c.cell_generation = grid_generation_[cell];
      const std::vector<GridEntry>& list = grid_[cell];
      for (; c.entry < list.size(); ++c.entry) {
        const GridEntry& e = list[c.entry];
        count_check();
        // The depth-extent test, from the entry alone; not within P's plane group, ordered by id.
        if (e.dmax <= near_limit && (group == 0 || e.plane_group != group)) continue;
        const uint32_t q = e.item;
        if (q >= c.base) break;  // cell lists grow in index order; newer items are checked below
        if (q == p || !alive_[q]) continue;
        const CellRange& s = cells_[q];
        if (std::max(r.x0, s.x0) != cx || std::max(r.y0, s.y0) != cy) continue;  // once per pair
        if (!may_draw_before(p, q)) return int32_t(q);
      }
    }
    for (; c.seen < items_.size(); ++c.seen) {
      const uint32_t q = c.seen;
      if (q == p || !alive_[q]) continue;
      const CellRange& s = cells_[q];
      if (s.x1 < r.x0 || r.x1 < s.x0 || s.y1 < r.y0 || r.y1 < s.y0) continue;  // no shared cell
      count_check();
      if (!may_draw_before(p, q)) return int32_t(q);
    }
    return none;
  }

  // --- splitting ---------------------------------------------------------------------------------

  struct Parts {
    int32_t far = none, near = none;
  };

  // Cuts item `a` by `plane` (whose eye side is `side`, +1 or -1). False when the plane does not cut
  // it into two pieces. Pieces that end up outside the view are dropped.
  bool split_item(uint32_t a, const Plane& plane, int side, Parts& parts) {
    if (classify_polygon(soup_of(a).points(polygon_of(a)), plane, eps_) != PlaneSide::spanning) return false;
    const Polygon source = polygon_of(a);  // copied: the fragment soup may grow under it
    SplitResult r = split_polygon(soup_of(a), source, plane, eps_, order_.fragments);
    if (r.front < 0 || r.back < 0) return false;  // one piece degenerate: not a real cut
    ++order_.splits;
    ++epoch_;  // the pieces start over: nobody counts as moved any more
    if (linked(a)) unlink(a);
    retire(a);
    auto add = [&](int64_t fragment_index) -> int32_t {
      SortItem item;
      if (!builder_.build(order_.fragments, uint32_t(fragment_index), true, item)) return none;
      items_.push_back(item);
      register_item(uint32_t(items_.size() - 1));
      return int32_t(items_.size() - 1);
    };
    int32_t front = add(r.front), back = add(r.back);
    parts = side > 0 ? Parts{back, front} : Parts{front, back};
    return true;
  }

  bool split_by_plane_of(uint32_t a, uint32_t b, Parts& parts) {
    if (side_[b] == 0) return false;
    return split_item(a, plane_of(polygon_of(b)), side_[b], parts);
  }

  // Cuts item `a` in half across its longest edge, through its vertex centroid.
  bool halve(uint32_t a, Parts& parts) {
    auto pts = soup_of(a).points(polygon_of(a));
    Vec3 centroid(0.0), longest(0.0);
    for (size_t k = 0; k < pts.size(); ++k) {
      centroid += pts[k];
      Vec3 e = pts[(k + 1) % pts.size()] - pts[k];
      if (glm::dot(e, e) > glm::dot(longest, longest)) longest = e;
    }
    centroid /= double(pts.size());
    double len = glm::length(longest);
    if (!(len > 0.0)) return false;
    Plane plane{longest / len, 0.0};
    plane.offset = glm::dot(plane.normal, centroid);
    return split_item(a, plane, 1, parts);
  }

  // P (the head) may hide Q and the pair has no order of whole polygons. `q_may_go_first`: Q could
  // go first but already did once (a cycle); otherwise P and Q pierce each other.
  bool resolve(uint32_t p, uint32_t q, bool q_may_go_first) {
    Parts parts;
    if (q_may_go_first) {
      // The cycle: cut the polygon moved twice by the other's plane; its far piece goes before P.
      if (split_by_plane_of(q, p, parts)) {
        place_front({parts.far, int32_t(p), parts.near});
        return true;
      }
      if (split_by_plane_of(p, q, parts)) {
        place_front({parts.far, int32_t(q), parts.near});
        return true;
      }
      if (halve(q, parts)) {
        place_front({parts.far, parts.near, int32_t(p)});
        return true;
      }
      return false;
    }
    // Piercing: each spans the other's plane. Cut P by Q's plane: far piece, Q, near piece.
    if (split_by_plane_of(p, q, parts)) {
      place_front({parts.far, int32_t(q), parts.near});
      return true;
    }
    if (split_by_plane_of(q, p, parts)) {
      place_front({parts.far, int32_t(p), parts.near});
      return true;
    }
    return false;
  }

  const FrameInput& input_;
  ItemBuilder& builder_;
  std::vector<SortItem>& items_;
  PainterOrder& order_;
  double eps_ = 0.0;
  size_t max_splits_ = 0, max_checks_ = 0, checks_ = 0;
  int nx_ = 1, ny_ = 1;
  double cell_w_ = 1.0, cell_h_ = 1.0;
  std::vector<std::vector<GridEntry>> grid_;
  std::vector<uint32_t> grid_dead_;        // retired items listed per cell since its last compaction
  std::vector<uint32_t> grid_generation_;  // compactions per cell
  std::vector<CellRange> cells_;
  std::vector<int8_t> side_;
  std::vector<int32_t> prev_, next_;
  std::vector<uint8_t> alive_;
  std::vector<uint32_t> mark_;
  uint32_t epoch_ = 1;
  std::vector<Cursor> cursor_;
  int32_t head_ = none;
};

}  // namespace

void newell_order(const FrameInput& input, ItemBuilder& builder, std::vector<SortItem>& items, PainterOrder& order) {
  order.items.reserve(items.size());
  Newell newell(input, builder, items, order);
  newell.run();
}

}  // namespace rr::painter_detail
