// Plane groups (see coplanar.hpp): each polygon's plane (normal signed so its largest component is
// positive, distance from the scene's centre) is hashed in coarse cells, entered in the neighbouring
// cell too near a boundary; each cell is swept along one in-plane axis, and a pair joins a group when
// each lies within the tolerance of the other's plane and their interiors overlap (separating axes).
#include "render/core/coplanar.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <numeric>

namespace rr {

namespace {

// Coplanar polygons' normals differ by about the tolerance over their size (2e-5 for a polygon of
// 5e-6 of the scene diagonal), their offsets from the centre by that times the diagonal: cells of
// 1e-3, with values within 2 % of a cell boundary entered in both cells, cover that.
constexpr double normal_cell = 1e-3;
constexpr double offset_cell = 1e-3;    // of the scene diagonal
constexpr double near_boundary = 0.02;  // of a cell: the value enters the neighbouring cell too

// A polygon under one cell key; the key is hashed to 64 bits, so that sorting moves 16 bytes and
// compares one word. Two cells sharing a hash (a chance of about cells² / 2^65 per soup) add
// candidate pairs, which are checked anyway, and are swept in the first one's in-plane axes.
struct Entry {
  uint64_t cell;
  uint32_t polygon;
};

uint64_t cell_hash(const int64_t (&c)[4]) {
  uint64_t h = 0x9E3779B97F4A7C15ull;
  for (int64_t v : c) {
    h ^= uint64_t(v) + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
  }
  return h ^ (h >> 31);
}

struct Extent {
  double u0, u1, v0, v1;
};

int dominant_axis(Vec3 n) {
  const Vec3 a = glm::abs(n);
  return a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
}

// The cells of one key component: its own, and the neighbour whose boundary is near. Cells are
// centred on integers, so that the 0 and ±1 components of axis-aligned normals sit mid-cell.
int cells_of(double x, int64_t out[2]) {
  const double f = std::floor(x + 0.5);
  const double r = x + 0.5 - f;
  out[0] = int64_t(f);
  if (r >= near_boundary && r <= 1.0 - near_boundary) return 1;
  out[1] = r < near_boundary ? out[0] - 1 : out[0] + 1;
  return 2;
}

struct GroupingFrame {
  Vec3 centre{0.0};
  double offset_scale = 1.0;  // 1 / offset cell size
  double tolerance = 0.0;
};

// Every key the polygon is entered under (usually one).
void add_entries(const Polygon& p, uint32_t index, const GroupingFrame& f, std::vector<Entry>& out) {
  const Vec3 a = glm::abs(p.normal);
  double top[3] = {a.x, a.y, a.z};
  std::sort(top, top + 3);
  const double dominant = p.normal[dominant_axis(p.normal)];
  // Two near-equal largest components: the sign is not well defined, so enter both.
  const bool ambiguous = top[2] - top[1] < 1e-3;
  for (double sign : {1.0, -1.0}) {
    if (!ambiguous && sign * dominant < 0.0) continue;
    const Vec3 n = sign * p.normal;
    const double values[4] = {n.x / normal_cell, n.y / normal_cell, n.z / normal_cell,
                              sign * (p.offset - glm::dot(p.normal, f.centre)) * f.offset_scale};
    int64_t c[4][2];
    int count[4];
    for (int k = 0; k < 4; ++k) count[k] = cells_of(values[k], c[k]);
    for (int i0 = 0; i0 < count[0]; ++i0)
      for (int i1 = 0; i1 < count[1]; ++i1)
        for (int i2 = 0; i2 < count[2]; ++i2)
          for (int i3 = 0; i3 < count[3]; ++i3) {
            const int64_t key[4] = {c[0][i0], c[1][i1], c[2][i2], c[3][i3]};
            out.push_back({cell_hash(key), index});
          }
  }
}

bool within_plane(std::span<const Vec3> points, const Polygon& plane, double tolerance) {
  for (const Vec3& q : points) {
    if (std::abs(glm::dot(plane.normal, q) - plane.offset) > tolerance) return false;
  }
  return true;
}

uint32_t find_root(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Pairs of one cell's polygons whose extents along the in-plane axes u, v overlap.
void join_cell(const PolygonSoup& soup, std::span<const Entry> cell, const GroupingFrame& f,
               std::vector<uint32_t>& parent, std::vector<std::pair<Extent, uint32_t>>& items) {
  const int drop = dominant_axis(soup.polygons[cell[0].polygon].normal);
  const int u = (drop + 1) % 3, v = (drop + 2) % 3;
  items.clear();
  for (const Entry& e : cell) {
    Extent x{INFINITY, -INFINITY, INFINITY, -INFINITY};
    for (const Vec3& q : soup.points(soup.polygons[e.polygon])) {
      x.u0 = std::min(x.u0, q[u]), x.u1 = std::max(x.u1, q[u]);
      x.v0 = std::min(x.v0, q[v]), x.v1 = std::max(x.v1, q[v]);
    }
    items.push_back({x, e.polygon});
  }
  std::sort(items.begin(), items.end(), [](const auto& a, const auto& b) { return a.first.u0 < b.first.u0; });
  for (size_t i = 0; i < items.size(); ++i) {
    const Extent& a = items[i].first;
    for (size_t j = i + 1; j < items.size() && items[j].first.u0 < a.u1 - f.tolerance; ++j) {
      const Extent& b = items[j].first;
      if (std::min(a.v1, b.v1) - std::max(a.v0, b.v0) <= f.tolerance) continue;
      const Polygon& p = soup.polygons[items[i].second];
      const Polygon& q = soup.polygons[items[j].second];
      const uint32_t rp = find_root(parent, items[i].second), rq = find_root(parent, items[j].second);
      if (rp == rq) continue;
      if (!within_plane(soup.points(q), p, f.tolerance) || !within_plane(soup.points(p), q, f.tolerance)) continue;
      if (!convex_overlap(soup.points(p), soup.points(q), p.normal, f.tolerance)) continue;
      parent[std::max(rp, rq)] = std::min(rp, rq);
    }
  }
}

}  // namespace

double coplanar_tolerance(const PolygonSoup& soup) {
  if (soup.positions.empty()) return 0.0;
  Vec3 lo = soup.positions[0], hi = lo;
  for (const Vec3& p : soup.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  const double magnitude = std::max(glm::length(lo), glm::length(hi));
  return std::max(coplanar_fraction * glm::length(hi - lo), 64.0 * DBL_EPSILON * magnitude);
}

bool convex_overlap(std::span<const Vec3> a, std::span<const Vec3> b, Vec3 normal, double tolerance) {
  const Vec3 origin = a[0];  // coordinates relative to one vertex keep their digits far from the origin
  auto separated_by_edges_of = [&](std::span<const Vec3> poly) {
    for (size_t k = 0; k < poly.size(); ++k) {
      const Vec3 edge = poly[(k + 1) % poly.size()] - poly[k];
      const Vec3 axis = glm::cross(normal, edge);
      const double length = glm::length(axis);
      if (length == 0.0) continue;
      double a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY;
      for (const Vec3& q : a)
        a0 = std::min(a0, glm::dot(axis, q - origin)), a1 = std::max(a1, glm::dot(axis, q - origin));
      for (const Vec3& q : b)
        b0 = std::min(b0, glm::dot(axis, q - origin)), b1 = std::max(b1, glm::dot(axis, q - origin));
      if (std::min(a1, b1) - std::max(a0, b0) <= tolerance * length) return true;
    }
    return false;
  };
  return !separated_by_edges_of(a) && !separated_by_edges_of(b);
}

void assign_plane_groups(PolygonSoup& soup) {
  const size_t n = soup.polygons.size();
  for (Polygon& p : soup.polygons) p.plane_group = 0;
  if (n < 2) return;
  Vec3 lo = soup.positions[0], hi = lo;
  for (const Vec3& p : soup.positions) lo = glm::min(lo, p), hi = glm::max(hi, p);
  GroupingFrame f;
  f.centre = 0.5 * (lo + hi);
  f.offset_scale = 1.0 / std::max(offset_cell * glm::length(hi - lo), DBL_MIN);
  f.tolerance = coplanar_tolerance(soup);
  std::vector<Entry> entries;
  entries.reserve(n + n / 8);
  for (uint32_t i = 0; i < n; ++i) add_entries(soup.polygons[i], i, f, entries);
  std::sort(entries.begin(), entries.end(),
            [](const Entry& a, const Entry& b) { return a.cell != b.cell ? a.cell < b.cell : a.polygon < b.polygon; });
  std::vector<uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<std::pair<Extent, uint32_t>> items;  // one cell's polygons, reused
  for (size_t begin = 0, end = 0; begin < entries.size(); begin = end) {
    while (end < entries.size() && entries[end].cell == entries[begin].cell) ++end;
    if (end - begin > 1) join_cell(soup, std::span<const Entry>(entries.data() + begin, end - begin), f, parent, items);
  }
  // Number the sets with two or more polygons by their lowest index (roots are the lowest).
  std::vector<uint32_t> size(n, 0), group(n, 0);
  for (uint32_t i = 0; i < n; ++i) ++size[find_root(parent, i)];
  uint32_t next = 0;
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t root = find_root(parent, i);
    if (size[root] < 2) continue;
    if (root == i) group[i] = ++next;
    soup.polygons[i].plane_group = group[root];
  }
}

}  // namespace rr
