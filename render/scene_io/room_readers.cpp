// JSON -> levels and rooms (docs/scene-format.md "Rooms" and "Levels"), the "level" member any
// element may carry (a level id -> its index in StaticGeometry::levels), and the view's level
// selection checked against a scene. Every problem goes to b.errors with its JSON Pointer; defaults
// that depend on the room's level (elevation, ceiling height) are resolved here.
#include "render/scene_io/errors.hpp"
#include "render/scene_io/scene_checks.hpp"
#include "render/scene_io/scene_json_detail.hpp"

#include <set>

namespace rr {

using nlohmann::json;

namespace {

// Above this many points the O(n^2) simplicity test would cost more than a request should.
constexpr size_t max_room_points = 4096;

std::string known_levels(const std::vector<Level>& levels) {
  if (levels.empty()) return "the scene has no levels";
  std::string out = "known levels:";
  for (const Level& l : levels) out += " \"" + quote_input(l.id) + "\"";
  return out;
}

int find_level(const std::vector<Level>* levels, const std::string& id) {
  if (!levels) return -1;
  for (size_t i = 0; i < levels->size(); ++i) {
    if ((*levels)[i].id == id) return int(i);
  }
  return -1;
}

void read_room_points(const ObjectReader& r, Room& room, const Bounds& b) {
  const size_t errors_before = b.errors.size();
  b.errors.attempt([&] {
    const json& points = r.array("points", true);
    if (points.size() < 3) throw_invalid(r.at("points"), "must hold at least 3 points");
    if (points.size() > max_room_points) {
      throw_too_large(r.at("points"), "must hold at most " + std::to_string(max_room_points) + " points");
    }
    for_each_element(points, r.at("points"), b.errors, [&](const json& point, const std::string& p) {
      room.points.push_back(read_vec2(point, p, b.coordinate));
    });
  });
  if (b.errors.size() != errors_before) return;
  if (std::string problem = simple_polygon_problem(room.points); !problem.empty()) {
    b.errors.add(r.at("points"), "must be a simple polygon: " + problem);
  }
}

}  // namespace

int read_level_ref(const json& element, const std::string& pointer, const Bounds& b) {
  if (!element.is_object()) return -1;
  auto it = element.find("level");
  if (it == element.end()) return -1;
  int index = -1;
  b.errors.attempt([&] {
    const std::string at = pointer_append(pointer, "level");
    if (!it->is_string()) throw_invalid(at, "must be a string: the id of one of /scene/levels");
    index = find_level(b.levels, it->get_ref<const std::string&>());
    if (index < 0) {
      throw_invalid(
          at, "names no level of /scene/levels (" + known_levels(b.levels ? *b.levels : std::vector<Level>{}) + ")");
    }
  });
  return index;
}

Level read_level(const json& value, const std::string& pointer, const Bounds& b) {
  ObjectReader r(value, pointer, b.errors, {"id", "elevation", "height", "viewable"});
  Level level;
  const size_t errors_before = b.errors.size();
  b.errors.attempt([&] { r.require("id"); });
  level.id = r.string("id", "");
  if (b.errors.size() == errors_before && level.id.empty()) b.errors.add(r.at("id"), "must not be empty");
  level.elevation = r.number("elevation", 0.0, b.coordinate);
  level.height = r.number("height", 2.5, b.length);
  level.viewable = r.boolean("viewable", true);
  return level;
}

// Level ids name levels in requests, so two levels may not share one.
void check_level_ids(const std::vector<Level>& levels, const std::string& pointer, ErrorList& errors) {
  std::set<std::string> seen;
  for (size_t i = 0; i < levels.size(); ++i) {
    if (!levels[i].id.empty() && !seen.insert(levels[i].id).second) {
      errors.add(pointer_append(pointer_append(pointer, i), "id"), "repeats the id of an earlier level");
    }
  }
}

Room read_room(const json& value, const std::string& pointer, const Bounds& b) {
  ObjectReader r(value, pointer, b.errors,
                 {"id", "points", "elevation", "floor", "floor_color", "floor_texture", "material", "ceiling",
                  "ceiling_height", "ceiling_color", "ceiling_texture", "level"});
  Room room;
  room.id = r.string("id", "");
  read_room_points(r, room, b);
  room.level = read_level_ref(value, pointer, b);
  const Level* level = room.level >= 0 ? &(*b.levels)[size_t(room.level)] : nullptr;
  room.elevation = r.number("elevation", level ? level->elevation : 0.0, b.coordinate);
  room.floor = r.boolean("floor", true);
  room.floor_color = read_surface_color(r, "floor_color", "floor_texture", read_color(json("#d9d4c7"), ""));
  room.floor_texture = read_texture(r, "floor_texture", b);
  room.floor_material = read_material(r);
  room.ceiling = r.boolean("ceiling", true);
  room.ceiling_height = r.number("ceiling_height", level ? level->height : 2.5, b.length);
  room.ceiling_color = read_surface_color(r, "ceiling_color", "ceiling_texture", read_color(json("#f0f0f0"), ""));
  room.ceiling_texture = read_texture(r, "ceiling_texture", b);
  return room;
}

void check_view_levels(const RenderOptions& options, const std::vector<Level>& levels, const std::string& pointer,
                       ErrorList& errors) {
  for (size_t i = 0; i < options.levels.size(); ++i) {
    if (find_level(&levels, options.levels[i]) < 0) {
      errors.add(pointer_append(pointer, i), "names no level of the scene (" + known_levels(levels) + ")");
    }
  }
}

void check_view_levels(const RenderOptions& options, const std::vector<Level>& levels) {
  ErrorList errors;
  check_view_levels(options, levels, "/options/levels", errors);
  errors.throw_if_any();
}

}  // namespace rr
