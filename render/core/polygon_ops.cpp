// Classification and splitting of convex polygons (see polygon_ops.hpp).
#include "render/core/polygon_ops.hpp"

#include <algorithm>

namespace rr {

PlaneSide classify_polygon(std::span<const Vec3> points, const Plane& plane, double epsilon) {
  bool any_front = false, any_back = false;
  for (const Vec3& p : points) {
    double d = plane.distance(p);
    any_front |= d > epsilon;
    any_back |= d < -epsilon;
  }
  if (any_front && any_back) return PlaneSide::spanning;
  if (any_front) return PlaneSide::front;
  if (any_back) return PlaneSide::back;
  return PlaneSide::on;
}

PolygonSoup make_fragment_soup(const PolygonSoup& source) {
  PolygonSoup soup;
  soup.materials = source.materials;
  soup.objects = source.objects;
  soup.uv_maps = source.uv_maps;
  return soup;
}

uint32_t append_polygon(PolygonSoup& to, const PolygonSoup& from, const Polygon& polygon) {
  Polygon copy = polygon;  // copied first: `polygon` may live in `to`, whose storage may move
  copy.first_vertex = uint32_t(to.positions.size());
  for (uint32_t i = 0; i < copy.vertex_count; ++i) {
    Vec3 p = from.positions[polygon.first_vertex + i];
    glm::vec3 n = from.normals[polygon.first_vertex + i];
    to.positions.push_back(p);
    to.normals.push_back(n);
  }
  to.polygons.push_back(copy);
  return uint32_t(to.polygons.size() - 1);
}

namespace {

struct CutVertex {
  Vec3 p;
  glm::vec3 n;
};

int64_t append_part(PolygonSoup& out, const Polygon& source, const std::vector<CutVertex>& part) {
  if (part.size() < 3) return -1;
  std::vector<Vec3> points;
  points.reserve(part.size());
  for (const CutVertex& v : part) points.push_back(v.p);
  if (!(polygon_area(points) > 0.0)) return -1;
  Polygon poly = source;
  poly.first_vertex = uint32_t(out.positions.size());
  poly.vertex_count = uint32_t(part.size());
  for (const CutVertex& v : part) {
    out.positions.push_back(v.p);
    out.normals.push_back(v.n);
  }
  out.polygons.push_back(poly);
  return int64_t(out.polygons.size() - 1);
}

}  // namespace

SplitResult split_polygon(const PolygonSoup& from, const Polygon& polygon, const Plane& plane, double epsilon,
                          PolygonSoup& out) {
  const Polygon source = polygon;  // `polygon` may live in `out`
  std::vector<CutVertex> front, back;
  const uint32_t n = source.vertex_count;
  std::vector<CutVertex> in(n);
  std::vector<double> d(n);
  for (uint32_t i = 0; i < n; ++i) {
    in[i] = {from.positions[source.first_vertex + i], from.normals[source.first_vertex + i]};
    d[i] = plane.distance(in[i].p);
  }
  for (uint32_t i = 0; i < n; ++i) {
    const CutVertex& a = in[i];
    const CutVertex& b = in[(i + 1) % n];
    double da = d[i], db = d[(i + 1) % n];
    int sa = da > epsilon ? 1 : (da < -epsilon ? -1 : 0);
    int sb = db > epsilon ? 1 : (db < -epsilon ? -1 : 0);
    if (sa >= 0) front.push_back(a);
    if (sa <= 0) back.push_back(a);
    if (sa * sb < 0) {  // the edge crosses the band: cut it where the signed distance is zero
      double t = da / (da - db);
      glm::vec3 nn = a.n + float(t) * (b.n - a.n);
      float len = glm::length(nn);
      CutVertex cut{a.p + t * (b.p - a.p), len > 0.0f ? nn / len : a.n};
      front.push_back(cut);
      back.push_back(cut);
    }
  }
  SplitResult r;
  r.front = append_part(out, source, front);
  r.back = append_part(out, source, back);
  return r;
}

namespace {

struct EdgePoint {
  double t;  // along the edge, 0 at its start
  uint32_t vertex;
};

// Vertices of one source polygon's fragments, sorted by x, so that an edge looks only at those
// within its x range (a floor split into thousands of fragments would otherwise cost m^2).
struct GroupVertices {
  std::vector<std::pair<double, uint32_t>> by_x;  // (x, vertex index)
};

// Vertices of the group strictly inside the edge a -> b (within epsilon of it), in order along it.
void points_on_edge(const PolygonSoup& soup, const GroupVertices& group, Vec3 a, Vec3 b, double epsilon,
                    std::vector<EdgePoint>& out) {
  out.clear();
  const Vec3 d = b - a;
  const double length2 = glm::dot(d, d);
  if (!(length2 > 0.0)) return;
  const double x0 = std::min(a.x, b.x) - epsilon, x1 = std::max(a.x, b.x) + epsilon;
  auto it = std::lower_bound(group.by_x.begin(), group.by_x.end(), std::pair{x0, uint32_t{0}});
  for (; it != group.by_x.end() && it->first <= x1; ++it) {
    const Vec3 p = soup.positions[it->second];
    if (p == a || p == b) continue;
    const double t = glm::dot(p - a, d) / length2;
    if (!(t > 0.0 && t < 1.0) || glm::length(p - (a + t * d)) > epsilon) continue;
    out.push_back({t, it->second});
  }
  std::sort(out.begin(), out.end(), [](const EdgePoint& x, const EdgePoint& y) { return x.t < y.t; });
  out.erase(std::unique(out.begin(), out.end(),
                        [&](const EdgePoint& x, const EdgePoint& y) {
                          return soup.positions[x.vertex] == soup.positions[y.vertex];
                        }),
            out.end());
}

}  // namespace

void close_t_junctions(PolygonSoup& fragments, double epsilon, const CancelToken* cancel) {
  CancelMeter meter(cancel, 16384);  // units: vertices grouped or edges searched
  // Fragments grouped by source id; only groups of two or more can have T-junctions.
  std::vector<std::pair<uint32_t, uint32_t>> by_id;  // (id, polygon index)
  by_id.reserve(fragments.polygons.size());
  for (uint32_t i = 0; i < fragments.polygons.size(); ++i) by_id.push_back({fragments.polygons[i].id, i});
  std::sort(by_id.begin(), by_id.end());
  std::vector<int32_t> group_of(fragments.polygons.size(), -1);
  std::vector<GroupVertices> groups;
  for (size_t k = 0; k < by_id.size();) {
    size_t end = k;
    while (end < by_id.size() && by_id[end].first == by_id[k].first) ++end;
    if (end - k >= 2) {
      GroupVertices g;
      for (size_t j = k; j < end; ++j) {
        const Polygon& f = fragments.polygons[by_id[j].second];
        group_of[by_id[j].second] = int32_t(groups.size());
        meter.add(f.vertex_count);
        for (uint32_t v = f.first_vertex; v < f.first_vertex + f.vertex_count; ++v)
          g.by_x.push_back({fragments.positions[v].x, v});
      }
      std::sort(g.by_x.begin(), g.by_x.end());
      groups.push_back(std::move(g));
    }
    k = end;
  }
  if (groups.empty()) return;
  PolygonSoup out = make_fragment_soup(fragments);
  out.positions.reserve(fragments.positions.size());
  out.normals.reserve(fragments.normals.size());
  std::vector<EdgePoint> on_edge;
  for (uint32_t i = 0; i < fragments.polygons.size(); ++i) {
    Polygon poly = fragments.polygons[i];
    const uint32_t first = poly.first_vertex, n = poly.vertex_count;
    poly.first_vertex = uint32_t(out.positions.size());
    for (uint32_t j = 0; j < n; ++j) {
      out.positions.push_back(fragments.positions[first + j]);
      out.normals.push_back(fragments.normals[first + j]);
      if (group_of[i] < 0) continue;
      meter.add(1 + on_edge.size());
      const Vec3 a = fragments.positions[first + j], b = fragments.positions[first + (j + 1) % n];
      // A vertex of this very fragment is never strictly inside one of its own (convex) edges.
      points_on_edge(fragments, groups[size_t(group_of[i])], a, b, std::max(epsilon, 1e-12 * glm::length(b - a)),
                     on_edge);
      for (const EdgePoint& e : on_edge) {
        out.positions.push_back(fragments.positions[e.vertex]);
        out.normals.push_back(fragments.normals[e.vertex]);
      }
    }
    poly.vertex_count = uint32_t(out.positions.size()) - poly.first_vertex;
    out.polygons.push_back(poly);
  }
  fragments = std::move(out);
}

}  // namespace rr
