// Rooms -> polygons: the floor polygon facing up at the room's elevation and the ceiling facing down
// at elevation + ceiling_height, each one convex polygon or ear-clipped triangles (add_face). World
// space, metres. A ceiling is one-sided (a closed object): a camera above it sees nothing of it, and
// it casts shadows from lights above it, as a ceiling seen only from inside its room should. The
// ceiling reaches ceiling_overlap_m under the walls along its outline (below).
#include "render/core/tessellate_detail.hpp"

#include <algorithm>
#include <cmath>

namespace rr::detail {

namespace {

// A room's outline usually runs along its walls' inner faces, where the ceiling meets the wall's
// top along a line. Seen from a light above, that joint is sealed only by the wall's top face,
// which faces the light and so casts nothing (closed objects cast with their faces turned away),
// and past the ceiling's edge a shadow map holds the wall's far outer face: the wall's lit face
// just below the ceiling then reads "lit" within a texel of the joint. So each edge of the ceiling
// that lies along a wall reaching the ceiling reaches 1 cm under it (about two texels of a 2048 map
// over a 10 m home): hidden inside the wall, it is not seen, and an exact shadow ray changes only
// where it passes within 1 cm of the joint. Edges with no wall under them stay where they are.
constexpr double ceiling_overlap_m = 0.01;
// How far outside a wall's footprint a room's edge may lie and still count as along that wall:
// Sweet Home 3D rooms drawn to a wall sit up to a few millimetres off its face.
constexpr double wall_contact_m = 0.005;

double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double length2 = glm::dot(ab, ab);
  const double t = length2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / length2, 0.0, 1.0) : 0.0;
  return glm::length(p - (a + t * ab));
}

// Whether the plan segment a-b lies within a wall's footprint (within wall_contact_m) and the
// wall reaches height y.
bool along_a_wall(Vec2 a, Vec2 b, double y, const std::vector<Wall>& walls) {
  for (const Wall& w : walls) {
    if (w.base > y || w.base + w.height < y - wall_contact_m) continue;
    const double reach = 0.5 * w.thickness + wall_contact_m;
    if (distance_to_segment(a, w.start, w.end) <= reach && distance_to_segment(b, w.start, w.end) <= reach) {
      return true;
    }
  }
  return false;
}

bool segments_cross(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const double d1 = cross2(b - a, c - a), d2 = cross2(b - a, d - a);
  const double d3 = cross2(d - c, a - c), d4 = cross2(d - c, b - c);
  return ((d1 > 0.0) != (d2 > 0.0)) && ((d3 > 0.0) != (d4 > 0.0)) && d1 != 0.0 && d2 != 0.0 && d3 != 0.0 && d4 != 0.0;
}

// The outline with each edge along a wall (at height y) moved ceiling_overlap_m outward: each
// vertex goes to where its two edges' moved lines meet. A vertex keeps its point where those lines
// are nearly parallel (collinear edges, one moved and one not) or meet far out (a corner sharper
// than about 66 degrees). The outline itself when the moved one crosses itself or turns an edge
// over (a notch narrower than twice the distance).
std::vector<Vec2> ceiling_outline(const std::vector<Vec2>& points, double y, const std::vector<Wall>& walls) {
  const size_t n = points.size();
  double twice_area = 0.0;
  for (size_t i = 0; i < n; ++i) twice_area += cross2(points[i], points[(i + 1) % n]);
  const double outward = twice_area > 0.0 ? 1.0 : -1.0;
  std::vector<double> moved(n);  // edge i runs from point i to point i + 1
  bool any = false;
  for (size_t i = 0; i < n; ++i) {
    moved[i] = along_a_wall(points[i], points[(i + 1) % n], y, walls) ? ceiling_overlap_m : 0.0;
    any = any || moved[i] > 0.0;
  }
  if (!any) return points;
  std::vector<Vec2> grown(points);
  for (size_t i = 0; i < n; ++i) {
    const size_t in = (i + n - 1) % n;
    const Vec2 p = points[i], before = points[in], after = points[(i + 1) % n];
    if (p == before || p == after || (moved[in] == 0.0 && moved[i] == 0.0)) continue;
    const Vec2 e1 = glm::normalize(p - before), e2 = glm::normalize(after - p);
    const Vec2 n1 = outward * Vec2(e1.y, -e1.x), n2 = outward * Vec2(e2.y, -e2.x);
    // x . n1 = p . n1 + moved[in] and x . n2 = p . n2 + moved[i], solved for x - p.
    const double det = cross2(n1, n2);
    if (std::abs(det) < 0.05 || 1.0 + glm::dot(n1, n2) < 0.6) continue;
    grown[i] = p + (moved[in] * Vec2(n2.y, -n2.x) - moved[i] * Vec2(n1.y, -n1.x)) / det;
  }
  for (size_t i = 0; i < n; ++i) {
    const size_t next = (i + 1) % n;
    if (glm::dot(grown[next] - grown[i], points[next] - points[i]) <= 0.0) return points;  // an edge turned over
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // neighbours through the closing edge
      if (segments_cross(grown[i], grown[i + 1], grown[j], grown[(j + 1) % n])) return points;
    }
  }
  return grown;
}

void add_room_surface(SoupBuilder& out, const std::vector<Vec2>& outline, double y, Vec3 outward, uint32_t material,
                      uint32_t object) {
  std::vector<Vec3> points;
  points.reserve(outline.size());
  for (Vec2 p : outline) points.push_back(plan_to_world(p, y));
  add_face(out, points, {}, outward, material, object);
}

}  // namespace

void add_rooms(SoupBuilder& out, const std::vector<Room>& rooms, const std::vector<Wall>& walls) {
  for (size_t i = 0; i < rooms.size(); ++i) {
    const Room& room = rooms[i];
    if (room.floor) {
      const uint32_t object = out.add_object(ElementRef::room(i), false, false);
      const uint32_t material = out.add_material({room.floor_color, 1.0f, room.floor_material, room.floor_texture});
      add_room_surface(out, room.points, room.elevation, {0.0, 1.0, 0.0}, material, object);
    }
    if (room.ceiling) {
      const uint32_t object = out.add_object(ElementRef::room(i), true, false);
      out.mark_ceiling(object);
      const uint32_t material = out.add_material({room.ceiling_color, 1.0f, {}, room.ceiling_texture});
      const double y = room.elevation + room.ceiling_height;
      add_room_surface(out, ceiling_outline(room.points, y, walls), y, {0.0, -1.0, 0.0}, material, object);
    }
  }
}

size_t estimate_room_polygons(const Room& room) {
  // Ear clipping gives at most n - 2 triangles per surface.
  const size_t per_surface = room.points.size() < 3 ? 0 : room.points.size() - 2;
  return per_surface * (size_t(room.floor) + size_t(room.ceiling));
}

}  // namespace rr::detail
