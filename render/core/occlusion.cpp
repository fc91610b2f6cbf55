// The depth pyramid and the front-to-back occlusion walk (see occlusion.hpp and docs/culling.md).
#include "render/core/occlusion.hpp"

#include "render/core/draw.hpp"
#include "render/core/frustum.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rr {

namespace {

// How far inside a polygon's edges a block must lie, in pixels: well beyond the rasterizer's vertex
// snapping (half a sub-pixel unit per axis), so every sample of the block is inside the snapped
// polygon however its pieces are rasterized.
constexpr double cover_margin = 1.0 / 64.0;
// The farthest a snapped vertex lies from the exact one, in pixels.
constexpr double snap_reach = 0.5 / double(subpixel_one) * 1.4142135623730951;
// A node with at most this many polygons that lies wholly in front of the pyramid over its rectangle
// is taken whole: nothing below it can be hidden by what is drawn so far, so the walk does not
// descend (a soup seen from the front, the first things met, furniture before the walls), which keeps
// its cost a small share of a frame. Larger nodes are still opened, so a walk that starts with an
// empty pyramid does not take the whole scene at once.
constexpr uint32_t bulk_polygons = 256;
// A polygon is drawn into the pyramid when its bounding sphere's radius spans this many pixels on
// screen or more: smaller ones cover few whole blocks, and on the homes they cost more walk time
// than the little they hide (a radius of 16 pixels hid 2 % more polygons for 40 % more walk time).
constexpr double occluder_min_pixels = 4.0 * occlusion_block;

double cross(double ax, double ay, double bx, double by) { return ax * by - ay * bx; }

}  // namespace

void DepthPyramid::reset(int width, int height) {
  width_ = width, height_ = height, raised_ = 0;
  dirty_x0_ = dirty_y0_ = 0, dirty_x1_ = dirty_y1_ = -1;
  int w = (width + occlusion_block - 1) / occlusion_block, h = (height + occlusion_block - 1) / occlusion_block;
  size_t count = 0;
  while (true) {
    if (levels_.size() <= count) levels_.emplace_back();
    Level& level = levels_[count++];
    level.w = w, level.h = h;
    level.min.assign(size_t(w) * size_t(h), 0.0);
    level.max.assign(size_t(w) * size_t(h), 0.0);
    if (w == 1 && h == 1) break;
    w = (w + 1) / 2, h = (h + 1) / 2;
  }
  levels_.resize(count);
}

void DepthPyramid::raise(int bx, int by, double inv_w) {
  double& v = levels_[0].min[size_t(by) * size_t(levels_[0].w) + size_t(bx)];
  if (inv_w <= v) return;
  if (v == 0.0) ++raised_;
  v = inv_w;
  levels_[0].max[size_t(by) * size_t(levels_[0].w) + size_t(bx)] = inv_w;
}

void DepthPyramid::refresh() const {
  if (dirty_x1_ < dirty_x0_) return;
  int bx0 = dirty_x0_, by0 = dirty_y0_, bx1 = dirty_x1_, by1 = dirty_y1_;
  dirty_x0_ = dirty_y0_ = 0, dirty_x1_ = dirty_y1_ = -1;
  for (size_t l = 1; l < levels_.size(); ++l) {
    bx0 /= 2, by0 /= 2, bx1 /= 2, by1 /= 2;
    const Level& fine = levels_[l - 1];
    Level& coarse = levels_[l];
    for (int y = by0; y <= by1; ++y) {
      for (int x = bx0; x <= bx1; ++x) {
        double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
        for (int dy = 0; dy < 2; ++dy) {
          for (int dx = 0; dx < 2; ++dx) {
            const int fx = 2 * x + dx, fy = 2 * y + dy;
            if (fx >= fine.w || fy >= fine.h) continue;
            const size_t at = size_t(fy) * size_t(fine.w) + size_t(fx);
            lo = std::min(lo, fine.min[at]), hi = std::max(hi, fine.max[at]);
          }
        }
        const size_t at = size_t(y) * size_t(coarse.w) + size_t(x);
        coarse.min[at] = lo, coarse.max[at] = hi;
      }
    }
  }
}

size_t DepthPyramid::add_polygon(std::span<const RasterVertex> v) {
  const size_t n = v.size();
  if (n < 3 || levels_.empty()) return 0;
  double area2 = 0.0;
  for (size_t k = 0; k < n; ++k) area2 += cross(v[k].x, v[k].y, v[(k + 1) % n].x, v[(k + 1) % n].y);
  if (!(std::abs(area2) > 1e-6)) return 0;
  const double sign = area2 > 0.0 ? 1.0 : -1.0;

  // 1/w is affine in screen space over the polygon's plane: from its largest fan triangle. Where the
  // rasterizer interpolates between snapped vertices, 1/w moves from this plane by at most `err`;
  // anywhere inside a fan triangle it lies between that triangle's least and greatest vertex 1/w.
  double least = std::numeric_limits<double>::infinity(), err = 0.0, best = 0.0;
  size_t best_k = 1;
  for (size_t k = 0; k < n; ++k) least = std::min(least, v[k].inv_w);
  for (size_t k = 1; k + 1 < n; ++k) {
    const RasterVertex* t[3] = {&v[0], &v[k], &v[k + 1]};
    const double a2 = std::abs(cross(t[1]->x - t[0]->x, t[1]->y - t[0]->y, t[2]->x - t[0]->x, t[2]->y - t[0]->y));
    double longest = 0.0, lo = t[0]->inv_w, hi = lo;
    for (int i = 0; i < 3; ++i) {
      const RasterVertex& a = *t[i];
      const RasterVertex& b = *t[(i + 1) % 3];
      longest = std::max(longest, (b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y));
      lo = std::min(lo, a.inv_w), hi = std::max(hi, a.inv_w);
    }
    longest = std::sqrt(longest);
    const double height = longest > 0.0 ? a2 / longest : 0.0;  // the triangle's least altitude
    // A well-shaped triangle: barycentric weights move by at most ~6 snap_reach / height each; a
    // sliver: only the bound between its vertices' depths holds, so the plane may be off by its range.
    err = std::max(err, height >= 2.0 ? 24.0 * snap_reach / height * (hi - lo) : (hi - lo) * 1.5);
    if (a2 > best) best = a2, best_k = k;
  }
  const RasterVertex &p0 = v[0], &p1 = v[best_k], &p2 = v[best_k + 1];
  const double det = cross(p1.x - p0.x, p1.y - p0.y, p2.x - p0.x, p2.y - p0.y);
  if (det == 0.0) return 0;
  const double ga = cross(p1.inv_w - p0.inv_w, p1.y - p0.y, p2.inv_w - p0.inv_w, p2.y - p0.y) / det;
  const double gb = cross(p1.x - p0.x, p1.inv_w - p0.inv_w, p2.x - p0.x, p2.inv_w - p0.inv_w) / det;
  auto plane = [&](double x, double y) { return p0.inv_w + ga * (x - p0.x) + gb * (y - p0.y); };
  // The slope's share of snapping: the plane read a snapped vertex's distance away.
  err += (std::abs(ga) + std::abs(gb)) * snap_reach;

  // Edges as a x + b y + c >= margin * length inside.
  struct Edge {
    double a, b, c;
  };
  Edge edges[64];
  std::vector<Edge> many;
  Edge* e = edges;
  if (n > 64) many.resize(n), e = many.data();
  size_t ne = 0;
  double ymin = v[0].y, ymax = v[0].y;
  for (size_t k = 0; k < n; ++k) {
    const RasterVertex& a = v[k];
    const RasterVertex& b = v[(k + 1) % n];
    ymin = std::min(ymin, a.y), ymax = std::max(ymax, a.y);
    const double dx = b.x - a.x, dy = b.y - a.y, len = std::sqrt(dx * dx + dy * dy);
    if (!(len > 1e-12)) continue;
    // sign * cross(b - a, p - a) / len >= cover_margin
    e[ne++] = {-sign * dy / len, sign * dx / len, sign * (dy * a.x - dx * a.y) / len - cover_margin};
  }
  const Level& base = levels_[0];
  auto interval = [&](double y, double& lo, double& hi) {
    lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
    for (size_t k = 0; k < ne; ++k) {
      const double rest = e[k].b * y + e[k].c;  // a x + rest >= 0
      if (e[k].a > 0.0) {
        lo = std::max(lo, -rest / e[k].a);
      } else if (e[k].a < 0.0) {
        hi = std::min(hi, -rest / e[k].a);
      } else if (rest < 0.0) {
        lo = std::numeric_limits<double>::infinity();
      }
    }
  };
  const int by0 = std::max(0, int(std::floor(ymin / occlusion_block)));
  const int by1 = std::min(base.h - 1, int(std::floor(ymax / occlusion_block)));
  size_t count = 0;
  int rx0 = base.w, ry0 = base.h, rx1 = -1, ry1 = -1;
  for (int by = by0; by <= by1; ++by) {
    const double y0 = by * occlusion_block, y1 = std::min(double(height_), y0 + occlusion_block);
    double l0, h0, l1, h1;
    interval(y0, l0, h0);
    interval(y1, l1, h1);
    const double lo = std::max(l0, l1), hi = std::min(h0, h1);
    if (!(lo < hi)) continue;
    const int bx0 = std::max(0, int(std::floor(lo / occlusion_block)));
    const int bx1 = std::min(base.w - 1, int(std::floor(hi / occlusion_block)));
    // The plane's least value over a block is at the corner its slopes point away from.
    const double dy_least = std::min(0.0, gb * (y1 - y0));
    for (int bx = bx0; bx <= bx1; ++bx) {
      const double x0 = bx * occlusion_block, x1 = std::min(double(width_), x0 + occlusion_block);
      if (x0 < lo || x1 > hi) continue;
      const double corner = plane(x0, y0) + std::min(0.0, ga * (x1 - x0)) + dy_least;
      const double bound = std::max(least, corner - err);
      if (!(bound > 0.0)) continue;
      raise(bx, by, bound);
      ++count;
      rx0 = std::min(rx0, bx), rx1 = std::max(rx1, bx), ry0 = std::min(ry0, by), ry1 = std::max(ry1, by);
    }
  }
  if (count > 0) {
    if (dirty_x1_ < dirty_x0_) {
      dirty_x0_ = rx0, dirty_y0_ = ry0, dirty_x1_ = rx1, dirty_y1_ = ry1;
    } else {
      dirty_x0_ = std::min(dirty_x0_, rx0), dirty_y0_ = std::min(dirty_y0_, ry0);
      dirty_x1_ = std::max(dirty_x1_, rx1), dirty_y1_ = std::max(dirty_y1_, ry1);
    }
  }
  return count;
}

template <class VisitEntry>
bool DepthPyramid::find_entry(int bx0, int by0, int bx1, int by1, VisitEntry visit) const {
  refresh();
  int level = 0;
  while (level + 1 < int(levels_.size()) &&
         ((bx1 >> level) - (bx0 >> level) > 1 || (by1 >> level) - (by0 >> level) > 1)) {
    ++level;
  }
  struct Entry {
    int level, x, y;
  };
  Entry stack[64];
  int top = 0;
  for (int y = by0 >> level; y <= by1 >> level; ++y) {
    for (int x = bx0 >> level; x <= bx1 >> level; ++x) stack[top++] = {level, x, y};
  }
  while (top > 0) {
    const Entry en = stack[--top];
    const Level& l = levels_[size_t(en.level)];
    const Visit answer = visit(en.level, l, size_t(en.y) * size_t(l.w) + size_t(en.x));
    if (answer == Visit::found) return true;
    if (answer == Visit::skip) continue;
    for (int dy = 1; dy >= 0; --dy) {
      for (int dx = 1; dx >= 0; --dx) {
        const int cx = 2 * en.x + dx, cy = 2 * en.y + dy, s = en.level - 1;
        const Level& f = levels_[size_t(s)];
        if (cx >= f.w || cy >= f.h) continue;
        if (cx < (bx0 >> s) || cx > (bx1 >> s) || cy < (by0 >> s) || cy > (by1 >> s)) continue;
        stack[top++] = {s, cx, cy};
      }
    }
  }
  return false;
}

bool DepthPyramid::hidden(int x0, int y0, int x1, int y1, double inv_w) const {
  x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, width_), y1 = std::min(y1, height_);
  if (x0 >= x1 || y0 >= y1 || levels_.empty()) return true;  // no pixel to show
  const int bx0 = x0 / occlusion_block, by0 = y0 / occlusion_block;
  const int bx1 = (x1 - 1) / occlusion_block, by1 = (y1 - 1) / occlusion_block;
  if ((bx1 - bx0 + 1) * (by1 - by0 + 1) <= 16) {  // a few blocks: read them directly
    const Level& l = levels_[0];
    for (int y = by0; y <= by1; ++y) {
      const double* row = l.min.data() + size_t(y) * size_t(l.w);
      for (int x = bx0; x <= bx1; ++x) {
        if (row[x] <= inv_w) return false;
      }
    }
    return true;
  }
  // An entry whose min is above inv_w has nothing behind; one whose max is at most inv_w (or a
  // level-0 block not above it) shows a block inside the rectangle that is not behind.
  return !find_entry(bx0, by0, bx1, by1, [inv_w](int level, const Level& l, size_t at) {
    if (l.min[at] > inv_w) return Visit::skip;
    return level == 0 || l.max[at] <= inv_w ? Visit::found : Visit::descend;
  });
}

bool DepthPyramid::in_front(int x0, int y0, int x1, int y1, double inv_w) const {
  if (raised_ == 0) return true;
  x0 = std::max(x0, 0), y0 = std::max(y0, 0), x1 = std::min(x1, width_), y1 = std::min(y1, height_);
  if (x0 >= x1 || y0 >= y1) return true;
  const int bx0 = x0 / occlusion_block, by0 = y0 / occlusion_block;
  const int bx1 = (x1 - 1) / occlusion_block, by1 = (y1 - 1) / occlusion_block;
  // A coarse entry whose max is at most inv_w has no such block below it; one above may have it
  // outside the rectangle only, so descend.
  return !find_entry(bx0, by0, bx1, by1, [inv_w](int level, const Level& l, size_t at) {
    if (l.max[at] <= inv_w) return Visit::skip;
    return level == 0 ? Visit::found : Visit::descend;
  });
}

bool project_box(const ViewTransform& view, Vec3 lo, Vec3 hi, ScreenBox& out) {
  double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0, w_min = x0, w_max = 0.0;
  // The corners as one corner plus the box's edges, each edge's clip-space step taken once.
  const Mat4& m = view.clip_from_world;
  const Vec4 base = m * Vec4(lo, 1.0);
  const Vec4 step[3] = {m[0] * (hi.x - lo.x), m[1] * (hi.y - lo.y), m[2] * (hi.z - lo.z)};
  const double half_w = 0.5 * double(view.width), half_h = 0.5 * double(view.height);
  for (int c = 0; c < 8; ++c) {
    Vec4 clip = base;
    if (c & 1) clip += step[0];
    if (c & 2) clip += step[1];
    if (c & 4) clip += step[2];
    // w is the view depth: a corner at or before the near plane leaves the box untestable.
    if (!(clip.w > view.near)) return false;
    const double inv_w = 1.0 / clip.w;  // as screen_from_clip, give or take rounding the margin covers
    const double sx = (clip.x * inv_w + 1.0) * half_w, sy = (1.0 - clip.y * inv_w) * half_h;
    x0 = std::min(x0, sx), x1 = std::max(x1, sx), y0 = std::min(y0, sy), y1 = std::max(y1, sy);
    w_min = std::min(w_min, clip.w), w_max = std::max(w_max, clip.w);
  }
  // One pixel more each way: snapping, and samples anywhere in a pixel whose centre is outside.
  auto clamp = [](double v, int hi_) { return int(std::clamp(v, -1.0, double(hi_) + 1.0)); };
  out.x0 = clamp(std::floor(x0) - 1.0, view.width), out.x1 = clamp(std::ceil(x1) + 1.0, view.width);
  out.y0 = clamp(std::floor(y0) - 1.0, view.height), out.y1 = clamp(std::ceil(y1) + 1.0, view.height);
  out.near_inv_w = 1.0 / w_min;
  out.far_inv_w = 1.0 / w_max;
  return true;
}

bool box_occluded(const DepthPyramid& pyramid, const ViewTransform& view, Vec3 lo, Vec3 hi, int eager, bool& tested) {
  ScreenBox box;
  tested = !pyramid.empty() && project_box(view, lo, hi, box);
  if (!tested) return false;
  const double widen = 1.0 + occlusion_margin - 2.0 * double(eager) * occlusion_margin;
  return pyramid.hidden(box.x0, box.y0, box.x1, box.y1, box.near_inv_w * widen);
}

void walk_occlusion(const SceneHierarchy& hierarchy, const PolygonSoup& frame_soup, std::span<const uint32_t> frame_of,
                    const OcclusionCandidates& candidates, const ViewTransform& view, int eager, OcclusionResult& out) {
  out.shown.assign(frame_soup.polygons.size(), 0);
  out.pyramid.reset(view.width, view.height);
  out.nodes_tested = out.nodes_occluded = out.occluders = out.nodes_outside_cells = 0;
  if (hierarchy.nodes.empty()) return;
  DepthPyramid& pyramid = out.pyramid;
  const Frustum frustum(view);
  const double widen = 1.0 + occlusion_margin - 2.0 * double(eager) * occlusion_margin;
  // Pixels per metre at unit view depth, vertically: a sphere of radius r at distance d spans about
  // 2 r * focal / d pixels.
  const double focal = view.clip_from_view[1][1] * 0.5 * double(view.height);
  const glm::vec3 eye(view.eye);
  DrawScratch scratch;

  auto emit = [&](const HierarchyNode& node) {
    for (uint32_t k = node.first; k < node.first + node.count; ++k) {
      const uint32_t h = hierarchy.polygons[k];
      const uint32_t f = frame_of.empty() ? h : frame_of[h];
      if (f == no_frame_polygon || !candidates.drawn[f]) continue;
      if (candidates.cells && !candidates.cells->polygon_reached(h)) continue;
      out.shown[f] = 1;
      if (!candidates.occluder[f]) continue;
      const PolygonSphere& s = hierarchy.spheres[h];
      const float d = glm::length(s.centre - eye);
      if (d > s.radius && double(s.radius) * focal < occluder_min_pixels * double(d)) continue;
      if (!project_polygon(view, frame_soup, frame_soup.polygons[f], scratch)) continue;
      // Nothing to raise where every block it could cover is already nearer than all of it.
      double x0 = scratch.screen[0].x, x1 = x0, y0 = scratch.screen[0].y, y1 = y0, near = 0.0;
      for (const RasterVertex& v : scratch.screen) {
        x0 = std::min(x0, v.x), x1 = std::max(x1, v.x), y0 = std::min(y0, v.y), y1 = std::max(y1, v.y);
        near = std::max(near, v.inv_w);
      }
      if (pyramid.hidden(int(std::floor(x0)), int(std::floor(y0)), int(std::ceil(x1)), int(std::ceil(y1)), near))
        continue;
      if (pyramid.add_polygon(scratch.screen) > 0) ++out.occluders;
    }
  };
  auto distance2 = [&](const HierarchyNode& n) {
    const glm::vec3 d = glm::max(glm::max(n.lo - eye, eye - n.hi), glm::vec3(0.0f));
    return glm::dot(d, d);
  };

  thread_local std::vector<uint32_t> kept_stack;
  std::vector<uint32_t>& stack = kept_stack;
  stack.assign(1, 0);
  while (!stack.empty()) {
    const uint32_t index = stack.back();
    const HierarchyNode& node = hierarchy.nodes[index];
    stack.pop_back();
    const Vec3 lo(node.lo), hi(node.hi);
    if (frustum.outside(lo, hi)) continue;
    ScreenBox box;
    const bool projected = (candidates.cells || !pyramid.empty()) && project_box(view, lo, hi, box);
    if (candidates.cells && !candidates.cells->node_reached(index, projected, box.x0, box.y0, box.x1, box.y1)) {
      ++out.nodes_outside_cells;
      continue;
    }
    const bool testable = !pyramid.empty() && projected;
    if (testable) {
      ++out.nodes_tested;
      if (pyramid.hidden(box.x0, box.y0, box.x1, box.y1, box.near_inv_w * widen)) {
        ++out.nodes_occluded;
        continue;
      }
    }
    const bool bulk =
        node.count <= bulk_polygons &&
        (!testable ? pyramid.empty() : pyramid.in_front(box.x0, box.y0, box.x1, box.y1, box.far_inv_w * widen));
    if (node.leaf() || bulk) {
      emit(node);
      continue;
    }
    const uint32_t first = uint32_t(&node - hierarchy.nodes.data()) + 1, second = node.second;
    const bool second_nearer = distance2(hierarchy.nodes[second]) < distance2(hierarchy.nodes[first]);
    stack.push_back(second_nearer ? first : second);  // the farther one waits
    stack.push_back(second_nearer ? second : first);
  }
  pyramid.finish();
}

}  // namespace rr
