// Sweet Home 3D Home.xml -> a request: every level as a scene level at its elevation (hidden ones
// not viewable, so not drawn by default) with its elements tagged, walls and openings
// (import_sh3d_walls.cpp), rooms as rooms (floor and ceiling), each top-level piece of furniture, lamp
// or furniture group as one piece of its models' parts (import_sh3d_models.cpp; a box of its size
// without models), each light source as a point light, and the observer camera as the camera. Centimetres -> metres;
// the plan's x and y are our x and z; Sweet Home 3D angles turn clockwise on the plan, ours counter-clockwise, so
// rotation_y = -angle.
#include "render/import/import.hpp"
#include "render/import/import_sh3d.hpp"
#include "render/scene_io/scene_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace rr {

using nlohmann::json;
using namespace import_detail;

namespace import_detail {

size_t Sh3dHome::line_of(const pugi::xml_node& node) const {
  ptrdiff_t offset = node.offset_debug();
  if (offset < 0 || line_starts.empty()) return 0;
  auto it = std::upper_bound(line_starts.begin(), line_starts.end(), size_t(offset));
  return size_t(it - line_starts.begin());
}

std::map<std::string, std::vector<Sh3dElement>> collect_elements(const pugi::xml_node& home, const Sh3dHome& h) {
  std::map<std::string, std::vector<Sh3dElement>> out;
  struct Open {
    pugi::xml_node parent;
    std::string pointer;
  };
  std::vector<Open> stack{{home, "/home"}};
  while (!stack.empty()) {
    Open open = std::move(stack.back());
    stack.pop_back();
    std::map<std::string, size_t> sibling_count;
    for (pugi::xml_node child : open.parent.children()) {
      if (child.type() != pugi::node_element) continue;
      const std::string name = child.name();
      const std::string pointer = open.pointer + "/" + name + "/" + std::to_string(sibling_count[name]++);
      if (name == "furnitureGroup") {
        stack.push_back({child, pointer});
      } else {
        out[name].push_back({child, pointer, h.line_of(child)});
      }
    }
  }
  // Groups were visited after their siblings; document order keeps the output stable and readable.
  for (auto& [name, elements] : out) {
    std::stable_sort(elements.begin(), elements.end(), [](const Sh3dElement& a, const Sh3dElement& b) {
      return a.node.offset_debug() < b.node.offset_debug();
    });
  }
  return out;
}

namespace {

[[noreturn]] void throw_attribute(const Sh3dElement& e, const char* name, const std::string& problem) {
  throw InputError(InputError::Kind::invalid, e.pointer,
                   "line " + std::to_string(e.line) + ": <" + e.node.name() + "> attribute " + name + " " + problem);
}

}  // namespace

double number_attribute(const Sh3dElement& e, const char* name, double fallback) {
  pugi::xml_attribute a = e.node.attribute(name);
  if (!a) return fallback;
  std::optional<double> value = parse_double(a.as_string());
  if (!value || std::abs(*value) > 1e8)
    throw_attribute(e, name, "'" + quote_input(a.as_string()) + "' is not a number");
  return *value;
}

double required_number(const Sh3dElement& e, const char* name) {
  if (!e.node.attribute(name)) throw_attribute(e, name, "is missing");
  return number_attribute(e, name, 0.0);
}

std::optional<Color> color_attribute(const pugi::xml_node& node, const char* name) {
  std::string_view text = node.attribute(name).as_string("");
  if (text.size() != 8 && text.size() != 6) return std::nullopt;
  unsigned value = 0;
  for (char c : text) {
    if (!std::isxdigit(static_cast<unsigned char>(c))) return std::nullopt;
    value = value * 16 + unsigned(std::isdigit(static_cast<unsigned char>(c)) ? c - '0' : std::tolower(c) - 'a' + 10);
  }
  return Color{float((value >> 16) & 0xff) / 255.0f, float((value >> 8) & 0xff) / 255.0f, float(value & 0xff) / 255.0f};
}

const Sh3dLevel& element_level(const Sh3dElement& e, const Sh3dHome& h) {
  static const Sh3dLevel ground;
  pugi::xml_attribute a = e.node.attribute("level");
  if (!a) return ground;
  auto it = h.levels.find(a.as_string());
  if (it == h.levels.end()) {
    throw InputError(InputError::Kind::invalid, e.pointer,
                     "line " + std::to_string(e.line) + ": <" + e.node.name() + "> names level '" +
                         quote_input(a.as_string()) + "', which the home does not define");
  }
  return it->second;
}

Sh3dLampLight sh3d_lamp_light(double power, Color source_color, Color home_light_color, std::optional<double> diameter,
                              double lamp_width_m) {
  // 5 x 255 x 255 / (100 cm/m)^2: the radiance factor with both colours 0..1 and distances in metres.
  constexpr double radiance_factor = 5.0 * 255.0 * 255.0 / 1.0e4;
  Sh3dLampLight lamp;
  lamp.color = Color{source_color.r * home_light_color.r, source_color.g * home_light_color.g,
                     source_color.b * home_light_color.b};
  lamp.intensity = radiance_factor * power * power;
  // A source without a diameter is a sphere of 3.25 cm radius; else the diameter is a fraction of the lamp's width.
  if (diameter) lamp.radius_m = *diameter * lamp_width_m / 2.0;
  return lamp;
}

void tag_level(json& element, const Sh3dLevel& level) {
  if (!level.id.empty()) element["level"] = level.id;
}

}  // namespace import_detail

namespace {

using Elements = std::map<std::string, std::vector<Sh3dElement>>;

const std::vector<Sh3dElement>& elements_named(const Elements& all, const std::string& name) {
  static const std::vector<Sh3dElement> none;
  auto it = all.find(name);
  return it == all.end() ? none : it->second;
}

std::string lower(std::string text) {
  for (char& c : text) c = char(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

pugi::xml_document load_home(std::string_view xml, Sh3dHome& h) {
  h.line_starts.push_back(0);
  for (size_t i = 0; i < xml.size(); ++i) {
    if (xml[i] == '\n') h.line_starts.push_back(i + 1);
  }
  pugi::xml_document doc;
  pugi::xml_parse_result parsed = doc.load_buffer(xml.data(), xml.size(), pugi::parse_default, pugi::encoding_utf8);
  if (!parsed) {
    auto it =
        std::upper_bound(h.line_starts.begin(), h.line_starts.end(), size_t(std::max<ptrdiff_t>(parsed.offset, 0)));
    const size_t line = size_t(it - h.line_starts.begin());
    throw_at_line(Kind::malformed, line, std::string("not well-formed XML: ") + parsed.description());
  }
  pugi::xml_node root = doc.document_element();
  if (std::strcmp(root.name(), "home") != 0) {
    throw InputError(Kind::malformed, "/" + std::string(root.name()),
                     "the root element is <" + std::string(root.name()) + ">, not Sweet Home 3D's <home>");
  }
  return doc;
}

void read_levels(const Elements& all, Sh3dHome& h) {
  for (const Sh3dElement& e : elements_named(all, "level")) {
    Sh3dLevel level;
    level.id = e.node.attribute("id").as_string("");
    level.elevation_m = number_attribute(e, "elevation", 0.0) / 100.0;
    level.floor_thickness_m = std::max(number_attribute(e, "floorThickness", 12.0) / 100.0, 0.001);
    level.height_m = std::max(number_attribute(e, "height", h.wall_height_m * 100.0) / 100.0, 0.01);
    level.viewable = e.node.attribute("visible").as_bool(true) && e.node.attribute("viewable").as_bool(true);
    if (!h.levels.count(level.id)) h.level_order.push_back(level.id);
    h.levels[level.id] = level;
  }
}

// The scene's levels in document order; a level without an id cannot be named, so none is emitted.
json levels_json(const Sh3dHome& h) {
  json out = json::array();
  for (const std::string& id : h.level_order) {
    const Sh3dLevel& l = h.levels.at(id);
    if (id.empty()) continue;
    out.push_back(
        {{"id", id}, {"elevation", round_m(l.elevation_m)}, {"height", round_m(l.height_m)}, {"viewable", l.viewable}});
  }
  return out;
}

std::vector<Sh3dOpening> read_openings(const Elements& all, const Sh3dHome& h) {
  std::vector<Sh3dOpening> out;
  for (const Sh3dElement& e : elements_named(all, "doorOrWindow")) {
    element_level(e, h);  // an unknown level is an error even for a door or window
    if (!e.node.attribute("visible").as_bool(true)) continue;
    Sh3dOpening o;
    o.element = &e;
    o.name = e.node.attribute("name").as_string("");
    const std::string words = lower(o.name + " " + e.node.attribute("catalogId").as_string(""));
    o.door = words.find("door") != std::string::npos;
    o.leaf = words.find("open") == std::string::npos && words.find("frame") == std::string::npos;
    o.centre = Vec2(required_number(e, "x"), required_number(e, "y")) / 100.0;
    const double angle = number_attribute(e, "angle", 0.0);
    o.axis = {std::cos(angle), std::sin(angle)};
    o.width = required_number(e, "width") / 100.0;
    o.depth = required_number(e, "depth") / 100.0;
    o.height = required_number(e, "height") / 100.0;
    o.elevation = number_attribute(e, "elevation", 0.0) / 100.0;
    o.level = e.node.attribute("level").as_string("");
    out.push_back(o);
  }
  return out;
}

// Rooms: the floor at the level's elevation, the ceiling at the level's height above it (the home's
// wall height without levels), as Sweet Home 3D draws them; a room shows neither is left out.
void add_rooms(const Elements& all, const Sh3dHome& h, const ImportOptions& options, Sh3dTextures& textures,
               json& rooms, std::vector<std::string>& warnings) {
  for (const Sh3dElement& e : elements_named(all, "room")) {
    const Sh3dLevel& level = element_level(e, h);
    const bool floor = e.node.attribute("floorVisible").as_bool(true);
    const bool ceiling = e.node.attribute("ceilingVisible").as_bool(true);
    if (!floor && !ceiling) continue;
    std::vector<Vec2> points;
    for (pugi::xml_node p : e.node.children("point")) {
      Sh3dElement point{p, e.pointer, e.line};
      Vec2 q{round_m(required_number(point, "x") / 100.0), round_m(required_number(point, "y") / 100.0)};
      if (points.empty() || q != points.back()) points.push_back(q);
    }
    while (points.size() > 1 && points.front() == points.back()) points.pop_back();
    const std::string name = e.node.attribute("name").as_string("");
    if (std::string problem = points.size() < 3 ? "fewer than 3 points" : simple_polygon_problem(points);
        !problem.empty()) {
      warnings.push_back("line " + std::to_string(e.line) + ": room '" + name + "' is not a simple polygon (" +
                         problem + "); it is left out");
      continue;
    }
    json plan = json::array();
    for (Vec2 q : points) plan.push_back(json_vec2(q));
    const Color color = color_attribute(e.node, "floorColor").value_or(Color{0.75f, 0.72f, 0.66f});
    const double height = level.id.empty() ? h.wall_height_m : level.height_m;
    json room = {{"id", "room " + name + " (" + e.pointer + ")"},
                 {"points", std::move(plan)},
                 {"elevation", round_m(level.elevation_m)},
                 {"floor", floor},
                 {"floor_color", json_color(color)},
                 {"ceiling", ceiling},
                 {"ceiling_height", round_m(height)}};
    if (auto c = color_attribute(e.node, "ceilingColor")) room["ceiling_color"] = json_color(*c);
    PlanBox box{points.front(), points.front()};
    for (Vec2 q : points) box.lo = glm::min(box.lo, q), box.hi = glm::max(box.hi, q);
    // A textured side shows its image, not its colour (white under the image, as Sweet Home 3D draws it).
    if (auto t = sh3d_texture(e, "floorTexture", options, textures, box)) {
      room["floor_texture"] = std::move(*t);
      room.erase("floor_color");
    }
    if (auto t = sh3d_texture(e, "ceilingTexture", options, textures, box)) {
      room["ceiling_texture"] = std::move(*t);
      room.erase("ceiling_color");
    }
    tag_level(room, level);
    rooms.push_back(std::move(room));
  }
}

// The piece's colour: its own, else its first coloured material, else grey.
Color piece_color(const pugi::xml_node& node) {
  if (auto c = color_attribute(node, "color")) return *c;
  for (pugi::xml_node m : node.children("material")) {
    if (auto c = color_attribute(m, "color")) return *c;
  }
  return Color{0.7f};
}

// Where an element of furniture goes, from its x, y, width, height, depth, angle and elevation (above
// its level); nullopt when it has no size.
std::optional<PiecePlacement> read_placement(const Sh3dElement& e, const Sh3dLevel& level) {
  PiecePlacement place;
  place.centre = Vec2(required_number(e, "x"), required_number(e, "y")) / 100.0;
  place.size = Vec3(required_number(e, "width"), required_number(e, "height"), required_number(e, "depth")) / 100.0;
  place.angle = number_attribute(e, "angle", 0.0);
  place.base = level.elevation_m + number_attribute(e, "elevation", 0.0) / 100.0;
  if (!(place.size.x > 1e-4 && place.size.y > 1e-4 && place.size.z > 1e-4)) return std::nullopt;
  return place;
}

// A piece standing where `place` says, holding `parts`: its box is the unit box of the parts.
Vec3 round_vec3(Vec3 v) { return {round_m(v.x), round_m(v.y), round_m(v.z)}; }

json piece_json(const std::string& id, const PiecePlacement& place, json parts) {
  return {{"type", "piece"},
          {"id", id},
          {"center", json_vec2(place.centre)},
          {"base", round_m(place.base)},
          {"size", json_vec3(place.size)},
          {"rotation_y", -place.angle * 180.0 / pi},
          {"parts", std::move(parts)}};
}

std::string element_label(const Sh3dElement& e) {
  return std::string(e.node.attribute("name").as_string("")) + " (" + e.pointer + ")";
}

// rotation_y as a 3x3 matrix acting on (x, y, z), as the tessellator turns (counter-clockwise seen
// from above: +X toward -Z); GLM matrices are indexed [column][row].
Mat3 turn_y(double rotation_y_deg) {
  const double a = radians(rotation_y_deg), c = std::cos(a), s = std::sin(a);
  Mat3 m(1.0);
  m[0][0] = c, m[2][0] = s;
  m[0][2] = -s, m[2][2] = c;
  return m;
}

// The rows [[a, b, c, tx], ...] that put a member's unit model, stretched by `stretch` and placed as
// a mesh solid of the member would have been (the box's middle rounded as such a solid's position
// was), into its group's unit box: u = G^-1 R_group^-1 (P_member - P_group + R_member (stretch * v)).
// The group's values are those its piece is written with, so the composition differs from placing
// the member by itself by rounding only (about 1e-16 of the coordinates).
json member_transform(const PiecePlacement& member, Vec3 stretch, const PiecePlacement& group) {
  const Vec3 member_centre = round_vec3({member.centre.x, member.base + 0.5 * member.size.y, member.centre.y});
  const Vec3 group_size = round_vec3(group.size);
  const Vec3 group_centre{round_m(group.centre.x), round_m(group.base) + 0.5 * group_size.y, round_m(group.centre.y)};
  Mat3 scale_in(1.0), scale_out(1.0);
  for (int k = 0; k < 3; ++k) {
    scale_in[k][k] = round_m(stretch[k]);
    scale_out[k][k] = group_size[k] > 1e-9 ? 1.0 / group_size[k] : 1.0;
  }
  const Mat3 unturn = glm::transpose(turn_y(-group.angle * 180.0 / pi));
  const Mat3 linear = scale_out * unturn * turn_y(-member.angle * 180.0 / pi) * scale_in;
  const Vec3 offset = scale_out * (unturn * (member_centre - group_centre));
  json rows = json::array();
  for (int row = 0; row < 3; ++row) rows.push_back({linear[0][row], linear[1][row], linear[2][row], offset[row]});
  return rows;
}

// The axes a unit model stretches on: the piece's size where the model has extent, 1 where it is flat.
Vec3 model_stretch(Vec3 size, Vec3 extent) {
  Vec3 out{1.0};
  for (int k = 0; k < 3; ++k) out[k] = extent[k] > 1e-9 ? size[k] : 1.0;
  return out;
}

// The pieces of furniture and lamps a group holds, at any depth, in document order.
void collect_members(const pugi::xml_node& group, const std::string& pointer, const Sh3dHome& h,
                     std::vector<Sh3dElement>& out) {
  std::map<std::string, size_t> sibling_count;
  for (pugi::xml_node child : group.children()) {
    if (child.type() != pugi::node_element) continue;
    const std::string name = child.name();
    const std::string at = pointer + "/" + name + "/" + std::to_string(sibling_count[name]++);
    if (!child.attribute("visible").as_bool(true)) continue;
    if (name == "furnitureGroup") {
      collect_members(child, at, h, out);
    } else if (name == "pieceOfFurniture" || name == "light") {
      out.push_back({child, at, h.line_of(child)});
    }
  }
}

// One top-level element of furniture: a piece, a lamp or a group; `members` holds a group's.
struct FurnitureItem {
  Sh3dElement element;
  std::vector<Sh3dElement> members;
};

// The top-level furniture in the order its solids are written: pieces of furniture, then lamps (so
// polygon ids keep the order they had when every piece was written separately), a group with the
// kind of its first member. Groups holding only doors and windows are none: those are openings.
std::vector<FurnitureItem> furniture_items(const pugi::xml_node& home, const Sh3dHome& h) {
  std::vector<FurnitureItem> pieces, lamps;
  std::map<std::string, size_t> sibling_count;
  for (pugi::xml_node child : home.children()) {
    if (child.type() != pugi::node_element) continue;
    const std::string name = child.name();
    if (name != "pieceOfFurniture" && name != "light" && name != "furnitureGroup") continue;
    FurnitureItem item{{child, "/home/" + name + "/" + std::to_string(sibling_count[name]++), h.line_of(child)}, {}};
    if (name == "furnitureGroup") {
      collect_members(child, item.element.pointer, h, item.members);
      if (item.members.empty()) continue;
    }
    const std::string kind = item.members.empty() ? name : item.members.front().node.name();
    (kind == "light" ? lamps : pieces).push_back(std::move(item));
  }
  pieces.insert(pieces.end(), std::make_move_iterator(lamps.begin()), std::make_move_iterator(lamps.end()));
  return pieces;
}

// A group as one piece: its box is the group's, and each member's model groups (a unit cube for a
// member without a model) are parts placed in it by the member's own transform.
std::optional<json> group_piece(const FurnitureItem& item, const PiecePlacement& group, const Sh3dLevel& level,
                                const ImportOptions& options, Sh3dModelCache& models, Sh3dTextures& textures,
                                size_t& skipped) {
  json parts = json::array();
  for (const Sh3dElement& m : item.members) {
    const std::optional<PiecePlacement> place = read_placement(m, level);
    if (!place) {
      ++skipped;
      continue;
    }
    Vec3 extent{1.0};
    std::optional<json> member_parts;
    if (options.furniture_models) member_parts = model_parts(m, options, models, textures, extent);
    if (!member_parts) {
      member_parts = json::array({{{"ref", unit_box_mesh(models)}, {"color", json_color(piece_color(m.node))}}});
      extent = Vec3{1.0};
    }
    const json transform = member_transform(*place, model_stretch(place->size, extent), group);
    const std::string member = m.node.attribute("name").as_string("");
    for (json& part : *member_parts) {
      part["name"] = member + (part.contains("name") ? " " + part["name"].get<std::string>() : "");
      part["transform"] = transform;
      parts.push_back(std::move(part));
    }
  }
  if (parts.empty()) return std::nullopt;
  return piece_json(element_label(item.element), group, std::move(parts));
}

// Every lamp's light sources as point lights (lamps inside groups too), in document order, lit by
// sh3d_lamp_light with the home's light colour. A lamp whose power is 0 is off and gives no light.
void add_lamp_lights(const Elements& all, const Sh3dHome& h, Color home_light_color, json& lights) {
  for (const Sh3dElement& e : elements_named(all, "light")) {
    const Sh3dLevel& level = element_level(e, h);
    // Lights carry no level: a lamp of a hidden level would light the levels shown.
    if (!e.node.attribute("visible").as_bool(true) || !level.viewable) continue;
    const std::optional<PiecePlacement> place = read_placement(e, level);
    if (!place) continue;
    const Vec2 centre = place->centre;
    const Vec3 size = place->size;
    const double angle = place->angle;
    const double power = std::clamp(number_attribute(e, "power", 0.5), 0.0, 1.0);
    if (!(power > 0.0)) continue;
    for (pugi::xml_node source : e.node.children("lightSource")) {
      Sh3dElement s{source, e.pointer, e.line};
      // Source coordinates are fractions of the piece's box: x along width, z up, y along depth from
      // the front (the piece's +y side on the plan) at 0 to its back at 1.
      const Vec2 local{(number_attribute(s, "x", 0.5) - 0.5) * size.x, (0.5 - number_attribute(s, "y", 0.5)) * size.z};
      const Vec2 plan = centre + Vec2(std::cos(angle) * local.x - std::sin(angle) * local.y,
                                      std::sin(angle) * local.x + std::cos(angle) * local.y);
      const double y = place->base + number_attribute(s, "z", 0.5) * size.y;
      std::optional<double> diameter;
      if (source.attribute("diameter")) diameter = number_attribute(s, "diameter", 0.0);
      const Sh3dLampLight lamp = sh3d_lamp_light(power, color_attribute(source, "color").value_or(Color{1.0f}),
                                                 home_light_color, diameter, size.x);
      lights.push_back({{"type", "point"},
                        {"id", e.pointer},
                        {"position", json_vec3({plan.x, y, plan.y})},
                        {"color", json_color(lamp.color)},
                        {"intensity", lamp.intensity},
                        {"attenuation", {lamp.radius_m * lamp.radius_m, 0.0, 1.0}}});
    }
  }
}

// One solid per top-level piece, lamp or group: a piece of its model's parts, or a box of its size
// when its model is not there (or boxes were asked for); each lamp's light sources as point lights.
void add_furniture(const pugi::xml_node& home, const Elements& all, const Sh3dHome& h, const ImportOptions& options,
                   Sh3dTextures& textures, json& solids, json& lights, ImportResult& result) {
  std::vector<std::string>& warnings = result.warnings;
  size_t skipped = 0;
  Sh3dModelCache models;
  for (const FurnitureItem& item : furniture_items(home, h)) {
    const Sh3dElement& e = item.element;
    const Sh3dLevel& level = element_level(e, h);
    if (!e.node.attribute("visible").as_bool(true)) continue;
    const std::optional<PiecePlacement> place = read_placement(e, level);
    if (!place) {
      ++skipped;
      continue;
    }
    std::optional<json> solid;
    Vec3 extent{1.0};
    if (!item.members.empty()) {
      solid = group_piece(item, *place, level, options, models, textures, skipped);
      if (!solid) continue;
    } else if (std::optional<json> parts;
               options.furniture_models && (parts = model_parts(e, options, models, textures, extent))) {
      solid = piece_json(element_label(e), *place, std::move(*parts));
    } else {
      solid = json{{"type", "box"},
                   {"id", element_label(e)},
                   {"center", json_vec2(place->centre)},
                   {"base", round_m(place->base)},
                   {"size", json_vec3(place->size)},
                   {"rotation_y", -place->angle * 180.0 / pi},
                   {"color", json_color(piece_color(e.node))}};
      if (!e.node.attribute("color")) {
        if (std::optional<json> texture = sh3d_texture(e, "", options, textures)) {
          solid->erase("color");
          (*solid)["texture"] = std::move(*texture);
        }
      }
    }
    tag_level(*solid, level);
    solids.push_back(std::move(*solid));
  }
  // Sweet Home 3D's default light colour when the home has no <environment lightColor>.
  const Color home_light_color =
      color_attribute(home.child("environment"), "lightColor").value_or(Color{208.0f / 255.0f});
  add_lamp_lights(all, h, home_light_color, lights);
  if (skipped) warnings.push_back(std::to_string(skipped) + " pieces of furniture with no size were left out");
  add_model_warnings(models, warnings);
  result.meshes = std::move(models.meshes);
}

// The observer camera: eye at (x, z, y) / 100, looking along yaw (0 looks toward +y on the plan,
// turning clockwise) and pitch (positive looks down); Sweet Home 3D's field of view is horizontal.
std::optional<json> observer_camera(const Elements& all, double aspect, const Box3& box) {
  for (const char* kind : {"observerCamera", "camera"}) {
    for (const Sh3dElement& e : elements_named(all, kind)) {
      if (std::string(e.node.attribute("attribute").as_string("")) != "observerCamera") continue;
      const Vec3 eye = Vec3(required_number(e, "x"), required_number(e, "z"), required_number(e, "y")) / 100.0;
      const double yaw = number_attribute(e, "yaw", 0.0), pitch = number_attribute(e, "pitch", 0.0);
      const Vec3 look{-std::sin(yaw) * std::cos(pitch), -std::sin(pitch), std::cos(yaw) * std::cos(pitch)};
      const double fov_x = std::clamp(number_attribute(e, "fieldOfView", pi / 3.0), 0.05, 3.0);
      const double fov_y_deg = std::clamp(2.0 * std::atan(std::tan(0.5 * fov_x) / aspect) * 180.0 / pi, 2.0, 160.0);
      const double reach =
          box.empty() ? 50.0 : glm::length(box.hi - box.lo) + glm::length(eye - 0.5 * (box.lo + box.hi));
      return json{{"position", json_vec3(eye)},
                  {"target", json_vec3(eye + look)},
                  {"fov_y", fov_y_deg},
                  {"near", 0.05},
                  {"far", std::max(round_m(2.0 * reach), 10.0)}};
    }
  }
  return std::nullopt;
}

}  // namespace

ImportResult import_sweethome3d(std::string_view home_xml, const ImportOptions& options) {
  const double scale = resolve_scale(options, ImportFormat::sweethome3d);
  if (scale != 0.01) {
    throw InputError(Kind::invalid, "/scale", "Sweet Home 3D homes are in centimetres: the scale is fixed at 0.01");
  }
  Sh3dHome h;
  pugi::xml_document doc = load_home(home_xml, h);
  pugi::xml_node root = doc.document_element();
  h.wall_height_m = root.attribute("wallHeight").as_double(250.0) / 100.0;
  if (!(h.wall_height_m > 0.0) || !std::isfinite(h.wall_height_m)) h.wall_height_m = 2.5;
  const Elements all = collect_elements(root, h);
  ImportResult result;
  read_levels(all, h);
  json walls = json::array(), solids = json::array(), rooms = json::array(),
       lights = json::array({default_sun_light()});
  Box3 box;
  Sh3dTextures textures;
  add_sh3d_walls(elements_named(all, "wall"), read_openings(all, h), h, options, textures, walls, solids,
                 result.warnings, box);
  add_rooms(all, h, options, textures, rooms, result.warnings);
  add_furniture(root, all, h, options, textures, solids, lights, result);
  add_texture_warnings(textures, result.warnings);
  const double aspect = double(options.width) / double(options.height);
  std::optional<json> camera = observer_camera(all, aspect, box);
  if (!camera) {
    result.warnings.push_back("the home has no observer camera; the camera shows the whole home from above");
    camera = camera_showing_box(box, aspect);
  }
  result.request = {{"scene",
                     {{"background", "#cce4fc"},
                      {"ambient", {{"intensity", 0.45}}},
                      {"walls", std::move(walls)},
                      {"solids", std::move(solids)},
                      {"rooms", std::move(rooms)},
                      {"lights", std::move(lights)}}},
                    {"camera", std::move(*camera)},
                    {"options", request_options(options)}};
  if (json levels = levels_json(h); !levels.empty()) result.request["scene"]["levels"] = std::move(levels);
  if (!options.mesh_refs) inline_mesh_refs(result);
  return result;
}

}  // namespace rr
