// R2V floor-plan annotation text ("x1 y1 x2 y2 category d1 d2" per line, image pixels, y down) ->
// a request: every `wall` segment a wall (0.12 m thick, 2.4 m high), every `door` segment an opening
// of the wall it lies on (a window when one side of it faces the outside, else an open doorway),
// sanitary and kitchen icons as boxes, a tiled floor over the walls' extent and a camera showing the
// whole plan. Pixel (x, y) becomes plan point (x, z) = scale * (x, y); docs/import.md gives the rules.
#include "render/import/import.hpp"
#include "render/import/import_common.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace rr {

using nlohmann::json;
using namespace import_detail;

namespace {

constexpr double wall_thickness_m = 0.12;
constexpr double wall_height_m = 2.4;
constexpr double door_height_m = 2.0;
constexpr double window_sill_m = 0.9;
constexpr double window_height_m = 1.2;
constexpr double floor_cell_m = 0.5;
// An opening belongs to a wall when both its ends lie within this many pixels of the wall's line
// (the annotations snap openings onto walls; 4 px is about 10 cm at the default scale).
constexpr double on_wall_px = 4.0;
// Clamped openings narrower than this are annotation slivers, not doors.
constexpr double min_opening_m = 0.2;

struct Segment {
  Vec2 a, b;  // pixels
  size_t line = 0;
};

// Icons drawn as boxes: category, height in metres, colour. Other icons and the room labels are
// listed in docs/import.md as not drawn.
struct Fixture {
  std::string_view category;
  double height_m;
  Color color;
};
constexpr std::array<Fixture, 4> fixtures = {{
    {"bathtub", 0.55, {0.93f, 0.93f, 0.95f}},
    {"toilet", 0.4, {0.95f, 0.95f, 0.95f}},
    {"washing_basin", 0.85, {0.9f, 0.92f, 0.95f}},
    {"cooking_counter", 0.9, {0.6f, 0.45f, 0.3f}},
}};

struct Plan {
  std::vector<Segment> walls, doors;
  std::vector<std::pair<Segment, const Fixture*>> icons;
  std::vector<Segment> entrances;
};

Plan parse_plan(std::string_view text) {
  Plan plan;
  LineReader lines(text);
  while (auto line = lines.next()) {
    std::vector<std::string_view> fields = split_fields(*line);
    if (fields.empty()) continue;
    const size_t n = lines.line_number();
    if (fields.size() < 5)
      throw_at_line(Kind::malformed, n,
                    "expected 'x1 y1 x2 y2 category', got " + std::to_string(fields.size()) + " fields");
    double c[4];
    for (int k = 0; k < 4; ++k) {
      auto v = parse_double(fields[size_t(k)]);
      if (!v || std::abs(*v) > 1e7) {
        throw_at_line(Kind::malformed, n, "coordinate '" + quote_input(fields[size_t(k)]) + "' is not a number");
      }
      c[k] = *v;
    }
    Segment s{{c[0], c[1]}, {c[2], c[3]}, n};
    std::string_view category = fields[4];
    if (category == "wall") {
      plan.walls.push_back(s);
    } else if (category == "door") {
      plan.doors.push_back(s);
    } else if (category == "entrance") {
      plan.entrances.push_back(s);
    } else {
      for (const Fixture& f : fixtures) {
        if (category == f.category) plan.icons.push_back({s, &f});
      }
    }
  }
  return plan;
}

double cross2(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }

// Does the ray from `origin` along `dir` cross any wall other than `skip`?
bool ray_hits_wall(Vec2 origin, Vec2 dir, const std::vector<Segment>& walls, size_t skip) {
  for (size_t w = 0; w < walls.size(); ++w) {
    if (w == skip) continue;
    const Vec2 e = walls[w].b - walls[w].a;
    const double denom = cross2(dir, e);
    if (std::abs(denom) < 1e-12) continue;
    const Vec2 d = walls[w].a - origin;
    const double t = cross2(d, e) / denom, u = cross2(d, dir) / denom;
    if (t > 0.0 && u >= 0.0 && u <= 1.0) return true;
  }
  return false;
}

bool boxes_touch(const Segment& box, Vec2 p, double margin) {
  return p.x >= std::min(box.a.x, box.b.x) - margin && p.x <= std::max(box.a.x, box.b.x) + margin &&
         p.y >= std::min(box.a.y, box.b.y) - margin && p.y <= std::max(box.a.y, box.b.y) + margin;
}

struct Placed {
  size_t wall = SIZE_MAX;
  double t0 = 0.0, t1 = 0.0;  // pixels along the wall from its start
};

// The wall a door segment lies on: both ends near its line, the largest overlap along it.
Placed place_opening(const Segment& door, const std::vector<Segment>& walls) {
  Placed best;
  double best_overlap = 0.0;
  for (size_t w = 0; w < walls.size(); ++w) {
    const Vec2 e = walls[w].b - walls[w].a;
    const double length = glm::length(e);
    if (length <= 0.0) continue;
    const Vec2 u = e / length;
    const double da = std::abs(cross2(u, door.a - walls[w].a)), db = std::abs(cross2(u, door.b - walls[w].a));
    if (da > on_wall_px || db > on_wall_px) continue;
    double t0 = glm::dot(u, door.a - walls[w].a), t1 = glm::dot(u, door.b - walls[w].a);
    if (t0 > t1) std::swap(t0, t1);
    const double overlap = std::min(t1, length) - std::max(t0, 0.0);
    if (overlap > best_overlap) best_overlap = overlap, best = {w, t0, t1};
  }
  return best;
}

json make_opening(const Plan& plan, const Placed& p, const Segment& door, double scale) {
  const Segment& wall = plan.walls[p.wall];
  const Vec2 u = glm::normalize(wall.b - wall.a);
  const Vec2 mid = wall.a + u * (0.5 * (p.t0 + p.t1));
  const Vec2 normal{-u.y, u.x};
  bool entrance = false;
  for (const Segment& e : plan.entrances) entrance = entrance || boxes_touch(e, mid, 2.0 * on_wall_px);
  // Outside on one side: a ray from the opening that meets no wall leaves the building.
  const bool exterior = !ray_hits_wall(mid + normal * on_wall_px, normal, plan.walls, p.wall) ||
                        !ray_hits_wall(mid - normal * on_wall_px, -normal, plan.walls, p.wall);
  const bool is_window = exterior && !entrance;
  const double length = glm::length(wall.b - wall.a);
  const double t0 = std::max(p.t0, 0.0), t1 = std::min(p.t1, length);
  json o = {{"id", "line " + std::to_string(door.line)},
            {"offset", round_m(t0 * scale)},
            {"width", round_m((t1 - t0) * scale)}};
  if (is_window) {
    o.update({{"type", "window"}, {"sill", window_sill_m}, {"height", window_height_m}});
  } else {
    o.update({{"type", "door"}, {"height", door_height_m}, {"leaf", false}});
  }
  return o;
}

// Openings attached to their walls: clamped to the wall, the later of two overlapping skipped.
void add_openings(const Plan& plan, double scale, json& walls, ImportResult& result) {
  std::vector<std::vector<std::pair<double, double>>> taken(plan.walls.size());
  for (const Segment& door : plan.doors) {
    const std::string where = "line " + std::to_string(door.line) + ": ";
    Placed p = place_opening(door, plan.walls);
    if (p.wall == SIZE_MAX) {
      result.warnings.push_back(where + "door lies on no wall; skipped");
      continue;
    }
    const double length = glm::length(plan.walls[p.wall].b - plan.walls[p.wall].a);
    const double t0 = std::max(p.t0, 0.0), t1 = std::min(p.t1, length);
    if ((t1 - t0) * scale < min_opening_m) {
      result.warnings.push_back(where + "door overlaps its wall by less than 0.2 m; skipped");
      continue;
    }
    if (t0 != p.t0 || t1 != p.t1) result.warnings.push_back(where + "door reaches past its wall's end; clamped");
    bool overlaps = false;
    for (auto [a, b] : taken[p.wall]) overlaps = overlaps || (t0 < b && t1 > a);
    if (overlaps) {
      result.warnings.push_back(where + "door overlaps another opening of its wall; skipped");
      continue;
    }
    taken[p.wall].push_back({t0, t1});
    walls[p.wall]["openings"].push_back(make_opening(plan, p, door, scale));
  }
}

}  // namespace

ImportResult import_r2v(std::string_view text, const ImportOptions& options) {
  const double scale = resolve_scale(options, ImportFormat::r2v);
  Plan plan = parse_plan(text);
  ImportResult result;
  // Zero-length walls have no direction; they are annotation noise.
  std::erase_if(plan.walls, [&](const Segment& s) {
    if (glm::length(s.b - s.a) * scale > 1e-6) return false;
    result.warnings.push_back("line " + std::to_string(s.line) + ": wall of zero length; skipped");
    return true;
  });
  if (plan.walls.empty()) throw InputError(Kind::invalid, "", "the plan has no walls");
  Box3 box;
  json walls = json::array();
  for (const Segment& s : plan.walls) {
    walls.push_back({{"id", "line " + std::to_string(s.line)},
                     {"start", json_vec2(s.a * scale)},
                     {"end", json_vec2(s.b * scale)},
                     {"thickness", wall_thickness_m},
                     {"height", wall_height_m},
                     {"openings", json::array()}});
    box.add({s.a.x * scale, 0.0, s.a.y * scale});
    box.add({s.b.x * scale, wall_height_m, s.b.y * scale});
  }
  add_openings(plan, scale, walls, result);
  json solids = json::array();
  for (const auto& [s, fixture] : plan.icons) {
    const Vec2 lo = glm::min(s.a, s.b) * scale, hi = glm::max(s.a, s.b) * scale;
    if (hi.x - lo.x < 1e-3 || hi.y - lo.y < 1e-3) continue;  // a degenerate icon box
    solids.push_back({{"type", "box"},
                      {"id", std::string(fixture->category) + " (line " + std::to_string(s.line) + ")"},
                      {"center", json_vec2(0.5 * (lo + hi))},
                      {"size", {round_m(hi.x - lo.x), fixture->height_m, round_m(hi.y - lo.y)}},
                      {"color", json_color(fixture->color)}});
  }
  // The floor: square tiles from the walls' minimum corner, enough to cover their extent.
  const int cells_x = std::max(1, int(std::ceil((box.hi.x - box.lo.x) / floor_cell_m)));
  const int cells_z = std::max(1, int(std::ceil((box.hi.z - box.lo.z) / floor_cell_m)));
  json floor = {
      {"origin", json_vec2({box.lo.x, box.lo.z})}, {"cells", {cells_x, cells_z}}, {"cell_size", floor_cell_m}};
  const double aspect = double(options.width) / double(options.height);
  result.request = {{"scene",
                     {{"background", "#dfe6ec"},
                      {"ambient", {{"intensity", 0.35}}},
                      {"floor", std::move(floor)},
                      {"walls", std::move(walls)},
                      {"solids", std::move(solids)},
                      {"lights", json::array({default_sun_light()})}}},
                    {"camera", camera_showing_box(box, aspect, 65.0)},  // steep: walls hide less of the rooms
                    {"options", request_options(options)}};
  return result;
}

}  // namespace rr
