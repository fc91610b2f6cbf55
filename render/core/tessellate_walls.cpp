// Walls -> polygons (world space, metres): joins first (mitres, T cuts), then each wall as a closed
// box with its openings cut through and the reveals closed, then door leaves and window panes.
// Faces are built in the wall's frame (u along the centreline from start, v toward the wall's left
// seen from start toward end, y above its base) and mapped to world by one affine map.
#include "render/core/tessellate_detail.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace rr::detail {
namespace {

// End points closer than this are one joint, and an end point closer than this to another wall's
// centreline lies on it (docs/scene-format.md "Joins").
constexpr double joint_tolerance_m = 1e-6;
// Walls meeting at less than 15 degrees are not joined: a mitre would reach 1 / tan(7.5 deg) = 7.6
// half thicknesses past the joint. A T uses the same limit for the same reason.
const double max_join_cosine = std::cos(radians(15.0));
const double min_tee_sine = std::sin(radians(15.0));
constexpr double leaf_thickness_m = 0.04;
constexpr double leaf_gap_m = 0.002;  // at each side and at the top of a door leaf

double cross2(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

struct WallFrame {
  Vec2 start, dir, left;  // plan (x, z); dir and left are unit
  double length = 0.0, half_thickness = 0.0;
  Vec2 point(double u, double v) const { return start + u * dir + v * left; }
  double u_of(Vec2 p) const { return glm::dot(p - start, dir); }
};

WallFrame make_frame(const Wall& w) {
  WallFrame f;
  f.start = w.start;
  f.length = glm::length(w.end - w.start);
  f.dir = (w.end - w.start) / f.length;
  f.left = {f.dir.y, -f.dir.x};  // +Y x dir: the walker's left seen from above
  f.half_thickness = 0.5 * w.thickness;
  return f;
}

// Where the left (v = +t/2) and right (v = -t/2) side lines of a wall end, as u along the
// centreline. Unjoined: 0 at the start and the length at the end.
struct EndCut {
  double left = 0.0, right = 0.0;
  double& side(double sigma) { return sigma > 0.0 ? left : right; }
  double side(double sigma) const { return sigma > 0.0 ? left : right; }
};
using WallCuts = std::array<EndCut, 2>;  // [0] start, [1] end

struct EndRef {
  uint32_t wall = 0;
  int end = 0;  // 0 start, 1 end
  Vec2 p;
  int partners = 0;      // ends of other walls within the joint tolerance
  uint32_t partner = 0;  // index of the last such end
};

// The point where the lines p + s*d and q + r*e meet (d, e unit), or nothing when nearly parallel.
std::optional<Vec2> intersect(Vec2 p, Vec2 d, Vec2 q, Vec2 e) {
  const double den = cross2(d, e);
  if (std::abs(den) < 1e-12) return std::nullopt;
  return p + d * (cross2(q - p, e) / den);
}

// Whether new cuts at one end keep the wall sound: each side line keeps its far half (so the two
// ends never cross) and every opening stays inside the cut footprint (1e-9 of the length slack;
// build_columns snaps the rest). A join that does not fit is not made.
bool cut_fits(const Wall& w, const WallFrame& f, int end, EndCut c) {
  if (!std::isfinite(c.left) || !std::isfinite(c.right)) return false;
  const double half = 0.5 * f.length, slack = 1e-9 * f.length;
  for (const Opening& o : w.openings) {
    if (end == 0 && o.offset < std::max(c.left, c.right) - slack) return false;
    if (end == 1 && o.offset + o.width > std::min(c.left, c.right) + slack) return false;
  }
  return end == 0 ? c.left < half && c.right < half : c.left > half && c.right > half;
}

// Two walls sharing one end point. Walking along A into the joint and on along B, A's side on the
// walker's left continues as B's side on the walker's left; the two pairs of side lines meet at
// the two ends of the mitre line, which also handles unequal thicknesses.
void mitre(const std::vector<Wall>& walls, const std::vector<WallFrame>& frames, std::vector<WallCuts>& cuts,
           const EndRef& a, const EndRef& b) {
  const WallFrame &fa = frames[a.wall], &fb = frames[b.wall];
  const Vec2 away_a = a.end == 0 ? fa.dir : -fa.dir, away_b = b.end == 0 ? fb.dir : -fb.dir;
  if (glm::dot(away_a, away_b) > max_join_cosine) return;
  if (std::abs(cross2(away_a, away_b)) < 1e-9) return;  // straight on: the square ends already meet
  const double walker_a = a.end == 1 ? 1.0 : -1.0, walker_b = b.end == 0 ? 1.0 : -1.0;
  EndCut ca, cb;
  for (double walker : {1.0, -1.0}) {
    const double sa = walker * walker_a, sb = walker * walker_b;
    const auto q =
        intersect(fa.point(0.0, sa * fa.half_thickness), fa.dir, fb.point(0.0, sb * fb.half_thickness), fb.dir);
    if (!q) return;
    ca.side(sa) = fa.u_of(*q);
    cb.side(sb) = fb.u_of(*q);
  }
  if (!cut_fits(walls[a.wall], fa, a.end, ca) || !cut_fits(walls[b.wall], fb, b.end, cb)) return;
  cuts[a.wall][size_t(a.end)] = ca;
  cuts[b.wall][size_t(b.end)] = cb;
}

// A's end lies on B's centreline: cut A back to the face of B on A's side.
bool cut_at_tee(const std::vector<Wall>& walls, const std::vector<WallFrame>& frames, std::vector<WallCuts>& cuts,
                const EndRef& a, uint32_t b) {
  const WallFrame &fa = frames[a.wall], &fb = frames[b];
  const Vec2 away_a = a.end == 0 ? fa.dir : -fa.dir;
  const double facing = glm::dot(away_a, fb.left);  // the sine of the angle between the walls
  if (std::abs(facing) < min_tee_sine) return false;
  const Vec2 face = fb.point(0.0, (facing > 0.0 ? 1.0 : -1.0) * fb.half_thickness);
  EndCut c;
  for (double side : {1.0, -1.0}) {
    const auto q = intersect(fa.point(0.0, side * fa.half_thickness), fa.dir, face, fb.dir);
    if (!q) return false;
    c.side(side) = fa.u_of(*q);
  }
  if (!cut_fits(walls[a.wall], fa, a.end, c)) return false;
  cuts[a.wall][size_t(a.end)] = c;
  return true;
}

std::vector<EndRef> find_shared_ends(const std::vector<Wall>& walls) {
  std::vector<EndRef> ends;
  for (uint32_t i = 0; i < walls.size(); ++i) {
    ends.push_back({i, 0, walls[i].start, 0, 0});
    ends.push_back({i, 1, walls[i].end, 0, 0});
  }
  std::vector<uint32_t> by_x(ends.size());
  for (uint32_t i = 0; i < by_x.size(); ++i) by_x[i] = i;
  std::sort(by_x.begin(), by_x.end(), [&](uint32_t l, uint32_t r) { return ends[l].p.x < ends[r].p.x; });
  for (size_t i = 0; i < by_x.size(); ++i) {  // sorted by x: only near neighbours in x are compared
    EndRef& e = ends[by_x[i]];
    for (size_t j = i + 1; j < by_x.size() && ends[by_x[j]].p.x - e.p.x <= joint_tolerance_m; ++j) {
      EndRef& o = ends[by_x[j]];
      if (o.wall == e.wall || glm::length(o.p - e.p) > joint_tolerance_m) continue;
      ++e.partners;
      e.partner = by_x[j];
      ++o.partners;
      o.partner = by_x[i];
    }
  }
  return ends;
}

// Ends joined to no other end that lie on the interior of another wall's centreline get a T cut,
// against the lowest-index such wall where the cut fits. Candidates are found by binary search
// along the axis in which the host wall is shorter: O(n log n) for rooms of axis-aligned walls;
// many long parallel diagonal walls can still cost O(n^2).
void cut_tees(const std::vector<Wall>& walls, const std::vector<WallFrame>& frames, std::vector<WallCuts>& cuts,
              const std::vector<EndRef>& ends) {
  std::vector<uint32_t> lonely;
  for (uint32_t i = 0; i < ends.size(); ++i) {
    if (ends[i].partners == 0) lonely.push_back(i);
  }
  std::vector<bool> done(ends.size(), false);
  std::array<std::vector<uint32_t>, 2> sorted{lonely, lonely};
  for (int axis = 0; axis < 2; ++axis) {
    std::sort(sorted[axis].begin(), sorted[axis].end(),
              [&](uint32_t l, uint32_t r) { return ends[l].p[axis] < ends[r].p[axis]; });
  }
  for (uint32_t b = 0; b < walls.size(); ++b) {
    const Vec2 lo = glm::min(walls[b].start, walls[b].end) - joint_tolerance_m;
    const Vec2 hi = glm::max(walls[b].start, walls[b].end) + joint_tolerance_m;
    const int axis = hi.x - lo.x <= hi.y - lo.y ? 0 : 1;
    const auto& list = sorted[axis];
    auto it =
        std::lower_bound(list.begin(), list.end(), lo[axis], [&](uint32_t e, double v) { return ends[e].p[axis] < v; });
    for (; it != list.end() && ends[*it].p[axis] <= hi[axis]; ++it) {
      const EndRef& e = ends[*it];
      if (done[*it] || e.wall == b) continue;
      const WallFrame& fb = frames[b];
      const double u = fb.u_of(e.p);
      const bool interior = u > joint_tolerance_m && u < fb.length - joint_tolerance_m;
      if (!interior || std::abs(cross2(fb.dir, e.p - fb.start)) > joint_tolerance_m) continue;
      done[*it] = cut_at_tee(walls, frames, cuts, e, b);
    }
  }
}

// Doc "Joins": exactly two walls sharing an end point are mitred; an end shared with no other
// wall that lies on another wall's centreline is cut back to that wall's face; the rest is left.
std::vector<WallCuts> compute_cuts(const std::vector<Wall>& walls, const std::vector<WallFrame>& frames) {
  std::vector<WallCuts> cuts(walls.size());
  for (size_t i = 0; i < walls.size(); ++i) {
    cuts[i] = {EndCut{0.0, 0.0}, EndCut{frames[i].length, frames[i].length}};
  }
  const std::vector<EndRef> ends = find_shared_ends(walls);
  for (uint32_t i = 0; i < ends.size(); ++i) {
    const EndRef& e = ends[i];
    if (e.partners == 1 && e.partner > i && ends[e.partner].partners == 1) {
      mitre(walls, frames, cuts, e, ends[e.partner]);
    }
  }
  cut_tees(walls, frames, cuts, ends);
  return cuts;
}

struct Interval {
  double lo = 0.0, hi = 0.0;
};

// A stretch of the wall along u whose cross-section (u, y) does not change: full wall, or the
// wall below and above one opening. Columns are contiguous: each starts where the previous ends.
struct Column {
  double u0 = 0.0, u1 = 0.0;        // along the centreline; the end columns follow the end cuts instead
  std::array<Interval, 2> solid{};  // wall material above the base, bottom to top
  int solid_count = 0;
  int opening = -1;  // index into Wall::openings, -1 for full wall
  Interval hole;     // the opening's void, above the base
};

// The void of an opening above the wall's base; within eps of the base or top snaps to it, so a
// door reaching the top leaves no head and no zero-height strip.
Interval hole_of(const Opening& o, double height, double eps) {
  Interval h{o.type == OpeningType::door ? 0.0 : o.sill, 0.0};
  h.hi = std::min(height, h.lo + o.height);
  if (h.lo <= eps) h.lo = 0.0;
  if (h.hi >= height - eps) h.hi = height;
  return h;
}

Column full_column(double u0, double u1, double height) {
  Column c;
  c.u0 = u0;
  c.u1 = u1;
  c.solid[0] = {0.0, height};
  c.solid_count = 1;
  return c;
}

Column opening_column(double u0, double u1, int opening, Interval hole, double height) {
  Column c;
  c.u0 = u0;
  c.u1 = u1;
  c.opening = opening;
  c.hole = hole;
  if (hole.lo > 0.0) c.solid[size_t(c.solid_count++)] = {0.0, hole.lo};
  if (hole.hi < height) c.solid[size_t(c.solid_count++)] = {hole.hi, height};
  return c;
}

// Splits the wall into columns at its openings (sorted along u). Stretches of full wall narrower
// than eps are left out and the neighbours made to touch; an end cut meeting an opening within eps
// is snapped to it (a square end flush with the opening, whose end face is then the opening's).
std::vector<Column> build_columns(const Wall& w, WallCuts& cuts, double eps) {
  std::vector<int> order;
  for (size_t k = 0; k < w.openings.size(); ++k) {
    const Interval hole = hole_of(w.openings[k], w.height, eps);
    if (w.openings[k].width > eps && hole.hi - hole.lo > eps) order.push_back(int(k));
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](int l, int r) { return w.openings[size_t(l)].offset < w.openings[size_t(r)].offset; });
  std::vector<Column> cols;
  double cursor = std::min(cuts[0].left, cuts[0].right);
  for (int k : order) {
    const Opening& o = w.openings[size_t(k)];
    const double end = o.offset + o.width;
    if (end - cursor <= eps) continue;  // overlaps the previous one (invalid input)
    if (cols.empty()) {
      cuts[0] = {std::min(cuts[0].left, o.offset), std::min(cuts[0].right, o.offset)};
      if (o.offset - cursor <= eps) cuts[0] = {o.offset, o.offset};
    }
    if (o.offset - cursor > eps) cols.push_back(full_column(cursor, o.offset, w.height));
    const double start = cols.empty() ? o.offset : cols.back().u1;
    cols.push_back(opening_column(start, end, k, hole_of(o, w.height, eps), w.height));
    cursor = end;
  }
  if (cols.empty()) return {full_column(cursor, std::max(cuts[1].left, cuts[1].right), w.height)};
  cuts[1] = {std::max(cuts[1].left, cursor), std::max(cuts[1].right, cursor)};
  if (std::max(cuts[1].left, cuts[1].right) - cursor > eps) {
    cols.push_back(full_column(cursor, std::max(cuts[1].left, cuts[1].right), w.height));
  } else {
    cuts[1] = {cursor, cursor};
  }
  return cols;
}

// One wall being emitted: its frame, cuts and columns, and the map from wall space to world.
struct WallBuild {
  SoupBuilder& out;
  const WallFrame& f;
  const Wall& wall;
  WallCuts cuts;
  std::vector<Column> cols;
  uint32_t material = 0, object = 0;
  uint32_t side_material[2] = {0, 0};  // the left and the right long face's

  Vec3 at(double u, double v, double y) const {
    const Vec2 p = f.point(u, v);
    return {p.x, wall.base + y, p.y};
  }
  Vec3 along() const { return {f.dir.x, 0.0, f.dir.y}; }
  Vec3 leftward() const { return {f.left.x, 0.0, f.left.y}; }
  // Extent of column c on side sigma (+1 left, -1 right): the end columns follow the end cuts.
  double u0(size_t c, double sigma) const { return c == 0 ? cuts[0].side(sigma) : cols[c].u0; }
  double u1(size_t c, double sigma) const { return c + 1 == cols.size() ? cuts[1].side(sigma) : cols[c].u1; }
  bool reaches(size_t c, bool top) const {
    const Column& col = cols[c];
    if (col.solid_count == 0) return false;
    return top ? col.solid[size_t(col.solid_count - 1)].hi == wall.height : col.solid[0].lo == 0.0;
  }
  void quad(Vec3 a, Vec3 b, Vec3 c, Vec3 d, Vec3 outward, uint32_t face_material) const {
    const Vec3 q[4] = {a, b, c, d};
    out.add_polygon(q, outward, face_material, object);
  }
  void quad(Vec3 a, Vec3 b, Vec3 c, Vec3 d, Vec3 outward) const { quad(a, b, c, d, outward, material); }
};

// The two long faces (left first), each piece by piece along u: a column's pieces bottom to top.
void add_long_faces(const WallBuild& b) {
  for (double sigma : {1.0, -1.0}) {
    const double v = sigma * b.f.half_thickness;
    // A side's texture measures from the wall's end at its viewer's left: the left side's end, the
    // right side's start, at the wall's base.
    const Vec2 anchor = sigma > 0.0 ? b.wall.end : b.wall.start;
    b.out.set_uv_frame({{anchor.x, b.wall.base, anchor.y}, 0.0});
    for (size_t c = 0; c < b.cols.size(); ++c) {
      for (int i = 0; i < b.cols[c].solid_count; ++i) {
        const Interval s = b.cols[c].solid[size_t(i)];
        const double u0 = b.u0(c, sigma), u1 = b.u1(c, sigma);
        b.quad(b.at(u0, v, s.lo), b.at(u1, v, s.lo), b.at(u1, v, s.hi), b.at(u0, v, s.hi), sigma * b.leftward(),
               b.side_material[sigma > 0.0 ? 0 : 1]);
      }
    }
  }
  b.out.set_uv_frame({});
}

// Top, then bottom: one convex piece per run of columns whose material reaches that face, along u.
void add_top_and_bottom(const WallBuild& b) {
  const double t = b.f.half_thickness;
  for (bool top : {true, false}) {
    const double y = top ? b.wall.height : 0.0;
    for (size_t c = 0; c < b.cols.size(); ++c) {
      if (!b.reaches(c, top)) continue;
      size_t e = c;
      while (e + 1 < b.cols.size() && b.reaches(e + 1, top)) ++e;
      b.quad(b.at(b.u0(c, 1.0), t, y), b.at(b.u1(e, 1.0), t, y), b.at(b.u1(e, -1.0), -t, y), b.at(b.u0(c, -1.0), -t, y),
             {0.0, top ? 1.0 : -1.0, 0.0});
      c = e;
    }
  }
}

// Start face, then end face, along the end cuts; bottom to top when an opening splits one.
void add_end_faces(const WallBuild& b) {
  const double t = b.f.half_thickness;
  for (int end = 0; end < 2; ++end) {
    const Column& col = end == 0 ? b.cols.front() : b.cols.back();
    const EndCut c = b.cuts[size_t(end)];
    for (int i = 0; i < col.solid_count; ++i) {
      const Interval s = col.solid[size_t(i)];
      b.quad(b.at(c.left, t, s.lo), b.at(c.right, -t, s.lo), b.at(c.right, -t, s.hi), b.at(c.left, t, s.hi),
             (end == 0 ? -1.0 : 1.0) * b.along());
    }
  }
}

// Reveals of the opening in column c: near jamb (at its offset), far jamb, head, sill. A jamb is
// the opening's void against the neighbouring column's material, so an opening flush with a
// square end or with another opening gets only the jamb pieces that bound material.
void add_reveals(const WallBuild& b, size_t c) {
  const Column& col = b.cols[c];
  const double t = b.f.half_thickness;
  for (int side = 0; side < 2; ++side) {
    if (side == 0 ? c == 0 : c + 1 == b.cols.size()) continue;
    const Column& next = b.cols[side == 0 ? c - 1 : c + 1];
    const double u = side == 0 ? col.u0 : col.u1;
    for (int i = 0; i < next.solid_count; ++i) {
      const double lo = std::max(col.hole.lo, next.solid[size_t(i)].lo);
      const double hi = std::min(col.hole.hi, next.solid[size_t(i)].hi);
      if (hi <= lo) continue;
      b.quad(b.at(u, -t, lo), b.at(u, t, lo), b.at(u, t, hi), b.at(u, -t, hi), (side == 0 ? 1.0 : -1.0) * b.along());
    }
  }
  const double head = col.hole.hi, sill = col.hole.lo;
  if (head < b.wall.height) {
    b.quad(b.at(col.u0, -t, head), b.at(col.u1, -t, head), b.at(col.u1, t, head), b.at(col.u0, t, head),
           {0.0, -1.0, 0.0});
  }
  if (sill > 0.0) {
    b.quad(b.at(col.u0, -t, sill), b.at(col.u1, -t, sill), b.at(col.u1, t, sill), b.at(col.u0, t, sill),
           {0.0, 1.0, 0.0});
  }
}

// A door leaf (a closed box: left, right, top, bottom, start side, end side) or a window pane (one
// quad facing the wall's left, in the middle of the thickness). The leaf is at most half the wall
// thick so none of its faces can coincide with the wall's.
void add_opening_fill(const WallBuild& b, size_t k, ElementRef element) {
  const Opening& o = b.wall.openings[k];
  if (o.type == OpeningType::door && !o.leaf) return;
  const double top = std::min(b.wall.height, (o.type == OpeningType::door ? 0.0 : o.sill) + o.height);
  if (o.type == OpeningType::door) {
    const double width = o.width - 2.0 * leaf_gap_m, height = top - leaf_gap_m;
    const double thickness = std::min(leaf_thickness_m, b.f.half_thickness);
    if (width <= 0.0 || height <= 0.0) return;
    const uint32_t object = b.out.add_object(element, true, false);
    const uint32_t material = b.out.add_material({o.color, 1.0f, MaterialParams{}});
    add_cuboid(b.out, b.at(o.offset + 0.5 * o.width, 0.0, 0.5 * height), b.leftward() * (0.5 * thickness),
               {0.0, 0.5 * height, 0.0}, b.along() * (-0.5 * o.width + leaf_gap_m), material, object);
    return;
  }
  const uint32_t object = b.out.add_object(element, false, false);
  const uint32_t material = b.out.add_material({o.color, o.opacity, MaterialParams{}});
  const double u0 = o.offset, u1 = o.offset + o.width;
  const Vec3 pane[4] = {b.at(u0, 0.0, o.sill), b.at(u1, 0.0, o.sill), b.at(u1, 0.0, top), b.at(u0, 0.0, top)};
  b.out.add_polygon(pane, b.leftward(), material, object);
}

}  // namespace

void add_walls(SoupBuilder& out, const std::vector<Wall>& walls) {
  std::vector<WallFrame> frames;
  for (const Wall& w : walls) frames.push_back(make_frame(w));
  const std::vector<WallCuts> cuts = compute_cuts(walls, frames);
  for (size_t i = 0; i < walls.size(); ++i) {
    const Wall& w = walls[i];
    // Lengths in this wall within 1e-9 of its size are treated as equal (flush openings, a door
    // reaching the top); the builder drops what that leaves without area.
    const double eps = 1e-9 * std::max({frames[i].length, w.height, w.thickness});
    WallBuild b{out, frames[i], w, cuts[i], {}, 0, 0};
    b.cols = build_columns(w, b.cuts, eps);
    b.object = out.add_object(ElementRef::wall(i), true, false);
    b.material = out.add_material({w.color, 1.0f, w.material});
    b.side_material[0] = out.add_material({w.left_color.value_or(w.color), 1.0f, w.material, w.left_texture});
    b.side_material[1] = out.add_material({w.right_color.value_or(w.color), 1.0f, w.material, w.right_texture});
    add_long_faces(b);
    add_top_and_bottom(b);
    add_end_faces(b);
    std::vector<int> column_of(w.openings.size(), -1);  // openings left out have no reveals
    for (size_t c = 0; c < b.cols.size(); ++c) {
      if (b.cols[c].opening >= 0) column_of[size_t(b.cols[c].opening)] = int(c);
    }
    for (size_t k = 0; k < w.openings.size(); ++k) {
      if (column_of[k] >= 0) add_reveals(b, size_t(column_of[k]));
      add_opening_fill(b, k, ElementRef::opening_of(i, k));
    }
  }
}

// Per side: one piece per full column (k + 1) and two per opening column; a top and a bottom piece
// per run (k + 1 each); two pieces per end face; per opening two jambs of two pieces, head, sill
// and six leaf faces. Hence 2 (3k + 1) + 2 (k + 1) + 4 + 12k = 20k + 8.
size_t estimate_wall_polygons(const Wall& wall) { return 20 * wall.openings.size() + 8; }

}  // namespace rr::detail
