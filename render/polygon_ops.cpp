// Classification and splitting of convex polygons (see polygon_ops.hpp).
#include "render/polygon_ops.hpp"

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

SplitResult split_polygon(const PolygonSoup& from, const Polygon& polygon, const Plane& plane,
                          double epsilon, PolygonSoup& out) {
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

}  // namespace rr
