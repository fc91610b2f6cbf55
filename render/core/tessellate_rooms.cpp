// Rooms -> polygons: the floor polygon facing up at the room's elevation and the ceiling facing down
// at elevation + ceiling_height, each one convex polygon or ear-clipped triangles (add_face). World
// space, metres. A ceiling is one-sided (a closed object): a camera above it sees nothing of it, and
// it casts shadows from lights above it, as a ceiling seen only from inside its room should.
#include "render/core/tessellate_detail.hpp"

namespace rr::detail {

namespace {

void add_room_surface(SoupBuilder& out, const Room& room, double y, Vec3 outward, uint32_t material, uint32_t object) {
  std::vector<Vec3> points;
  points.reserve(room.points.size());
  for (Vec2 p : room.points) points.push_back(plan_to_world(p, y));
  add_face(out, points, {}, outward, material, object);
}

}  // namespace

void add_rooms(SoupBuilder& out, const std::vector<Room>& rooms) {
  for (size_t i = 0; i < rooms.size(); ++i) {
    const Room& room = rooms[i];
    if (room.floor) {
      const uint32_t object = out.add_object(ElementRef::room(i), false, false);
      const uint32_t material = out.add_material({room.floor_color, 1.0f, room.floor_material});
      add_room_surface(out, room, room.elevation, {0.0, 1.0, 0.0}, material, object);
    }
    if (room.ceiling) {
      const uint32_t object = out.add_object(ElementRef::room(i), true, false);
      out.mark_ceiling(object);
      const uint32_t material = out.add_material({room.ceiling_color, 1.0f, {}});
      add_room_surface(out, room, room.elevation + room.ceiling_height, {0.0, -1.0, 0.0}, material, object);
    }
  }
}

size_t estimate_room_polygons(const Room& room) {
  // Ear clipping gives at most n - 2 triangles per surface.
  const size_t per_surface = room.points.size() < 3 ? 0 : room.points.size() - 2;
  return per_surface * (size_t(room.floor) + size_t(room.ceiling));
}

}  // namespace rr::detail
