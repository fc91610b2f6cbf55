// Cells and portals (render/core/cells.hpp, docs/culling.md "Cells"): what the derivation finds in
// small plans built for each case (an L-shaped room with one door to a corridor, two rooms joined
// where no wall parts them, rooms joined by a window only, two levels joined by a stairwell, walls
// that do not close, walls without rooms), what a portal walk from a camera reaches there, and the
// nine Sweet Home 3D homes of ../shared: their cells against their rooms (skipped without it).
#include "render/core/cells.hpp"
#include "render/import/import_files.hpp"
#include "render/pipelines/render.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>

namespace rr {
namespace {

using nlohmann::json;

json cells_wall(double x0, double z0, double x1, double z1, json openings = json::array()) {
  return {{"start", {x0, z0}}, {"end", {x1, z1}}, {"thickness", 0.15}, {"height", 2.5}, {"openings", openings}};
}

json cells_room(const std::string& id, std::vector<std::array<double, 2>> points) {
  json p = json::array();
  for (const auto& [x, z] : points) p.push_back({x, z});
  return {{"id", id}, {"points", p}};
}

// The four walls of the rectangle [x0, x1] x [z0, z1].
void cells_rectangle(json& walls, double x0, double z0, double x1, double z1) {
  walls.push_back(cells_wall(x0, z0, x1, z0));
  walls.push_back(cells_wall(x1, z0, x1, z1));
  walls.push_back(cells_wall(x1, z1, x0, z1));
  walls.push_back(cells_wall(x0, z1, x0, z0));
}

PreparedScene cells_scene(const json& scene) { return prepare_scene(request_from_json({{"scene", scene}}).scene); }

// The cell labelled with the room `id`, or no_cell.
uint32_t room_cell(const PreparedScene& s, const std::string& id) {
  const std::vector<Room>& rooms = s.scene.geometry.rooms;
  for (uint32_t c = 0; c < s.cells->cells.size(); ++c) {
    const int r = s.cells->cells[c].room;
    if (r >= 0 && rooms[size_t(r)].id == id) return c;
  }
  return no_cell;
}

// The undirected portals of `kind` as (lower cell, higher cell) pairs, one entry per portal.
std::multiset<std::pair<uint32_t, uint32_t>> portals_of(const SceneCells& cells, PortalKind kind) {
  std::multiset<std::pair<uint32_t, uint32_t>> out;
  for (const Portal& p : cells.portals) {
    if (p.kind == kind && p.from < p.to) out.insert({p.from, p.to});
  }
  return out;
}

// The cells a portal walk reaches from `eye` looking at `target` (a 320 x 180 frame, 60 degrees).
std::vector<uint8_t> cells_reached(const SceneCells& cells, Vec3 eye, Vec3 target) {
  Camera camera;
  camera.position = eye, camera.target = target, camera.near = 0.05;
  CellWalk walk;
  walk_cells(cells, cell_conditions(cells, {}), cell_viewpoint(make_view(camera, 320, 180)), walk);
  return walk.reached;
}

TEST(Cells, LShapedRoomWithOneDoorToACorridor) {
  // A 6 x 6 m outline; inside, a corridor [3, 6] x [3, 4.5] and a closet above it; the rest is the
  // L-shaped room, joined to the corridor by one door.
  json walls = json::array();
  cells_rectangle(walls, 0, 0, 6, 6);
  walls.push_back(cells_wall(3, 3, 6, 3, {{{"type", "door"}, {"offset", 1.0}, {"width", 0.9}}}));
  walls.push_back(cells_wall(3, 3, 3, 6));
  walls.push_back(cells_wall(3, 4.5, 6, 4.5));
  const json rooms = {cells_room("L", {{0, 0}, {6, 0}, {6, 3}, {3, 3}, {3, 6}, {0, 6}}),
                      cells_room("corridor", {{3, 3}, {6, 3}, {6, 4.5}, {3, 4.5}}),
                      cells_room("closet", {{3, 4.5}, {6, 4.5}, {6, 6}, {3, 6}})};
  const PreparedScene s = cells_scene({{"walls", walls}, {"rooms", rooms}});
  const SceneCells& cells = *s.cells;
  ASSERT_TRUE(cells.derived());
  EXPECT_EQ(cells.cells.size(), 4u);  // the outside and one per room
  const uint32_t l = room_cell(s, "L"), corridor = room_cell(s, "corridor"), closet = room_cell(s, "closet");
  ASSERT_NE(l, no_cell);
  ASSERT_NE(corridor, no_cell);
  ASSERT_NE(closet, no_cell);
  EXPECT_EQ(portals_of(cells, PortalKind::opening),
            (std::multiset<std::pair<uint32_t, uint32_t>>{{std::min(l, corridor), std::max(l, corridor)}}));
  EXPECT_TRUE(portals_of(cells, PortalKind::boundary).empty());
  // From the L's far arm looking at the door, the corridor is reached and the closet is not; looking
  // away from the door, neither.
  const std::vector<uint8_t> at_door = cells_reached(cells, {1.5, 1.6, 1.5}, {4.45, 1.0, 3.0});
  EXPECT_TRUE(at_door[l] && at_door[corridor]);
  EXPECT_FALSE(at_door[closet]);
  const std::vector<uint8_t> away = cells_reached(cells, {1.5, 1.6, 1.5}, {0.0, 1.0, 5.0});
  EXPECT_TRUE(away[l]);
  EXPECT_FALSE(away[corridor] || away[closet]);
}

TEST(Cells, TwoRoomsJoinedWhereNoWallPartsThem) {
  json walls = json::array();
  cells_rectangle(walls, 0, 0, 8, 4);
  const json rooms = {cells_room("A", {{0, 0}, {4, 0}, {4, 4}, {0, 4}}),
                      cells_room("B", {{4, 0}, {8, 0}, {8, 4}, {4, 4}})};
  const PreparedScene s = cells_scene({{"walls", walls}, {"rooms", rooms}});
  const SceneCells& cells = *s.cells;
  EXPECT_EQ(cells.cells.size(), 3u);
  const uint32_t a = room_cell(s, "A"), b = room_cell(s, "B");
  ASSERT_NE(a, no_cell);
  ASSERT_NE(b, no_cell);
  const auto boundary = portals_of(cells, PortalKind::boundary);
  EXPECT_FALSE(boundary.empty());
  for (const auto& pair : boundary) EXPECT_EQ(pair, std::make_pair(std::min(a, b), std::max(a, b)));
  EXPECT_TRUE(portals_of(cells, PortalKind::opening).empty());
  // From A, looking into B across the boundary, B is reached.
  EXPECT_TRUE(cells_reached(cells, {1.0, 1.6, 2.0}, {7.0, 1.0, 2.0})[b]);
}

TEST(Cells, RoomsJoinedByAWindowOnly) {
  json walls = json::array();
  cells_rectangle(walls, 0, 0, 8, 4);
  walls.push_back(cells_wall(4, 0, 4, 4, {{{"type", "window"}, {"offset", 1.5}, {"width", 1.0}}}));
  const json rooms = {cells_room("A", {{0, 0}, {4, 0}, {4, 4}, {0, 4}}),
                      cells_room("B", {{4, 0}, {8, 0}, {8, 4}, {4, 4}})};
  const PreparedScene s = cells_scene({{"walls", walls}, {"rooms", rooms}});
  const SceneCells& cells = *s.cells;
  EXPECT_EQ(cells.cells.size(), 3u);
  const uint32_t a = room_cell(s, "A"), b = room_cell(s, "B");
  ASSERT_NE(a, no_cell);
  ASSERT_NE(b, no_cell);
  EXPECT_EQ(portals_of(cells, PortalKind::opening),
            (std::multiset<std::pair<uint32_t, uint32_t>>{{std::min(a, b), std::max(a, b)}}));
  EXPECT_TRUE(portals_of(cells, PortalKind::boundary).empty());
  // The window's portal spans its sill to its head (0.9 to 2.1 m), not the wall's height.
  for (const Portal& p : cells.portals) {
    if (p.kind != PortalKind::opening) continue;
    for (uint32_t k = 0; k < p.count; ++k) {
      for (int q = 0; q < cells.shapes[p.first + k].count; ++q) {
        const double y = cells.shapes[p.first + k].corners[size_t(q)].y;
        EXPECT_TRUE(y > 0.89 && y < 2.11) << y;
      }
    }
  }
  EXPECT_TRUE(cells_reached(cells, {1.0, 1.5, 2.0}, {7.0, 1.5, 2.0})[b]);   // through the window
  EXPECT_FALSE(cells_reached(cells, {1.0, 1.5, 2.0}, {1.5, 1.5, 4.0})[b]);  // the window out of view
}

TEST(Cells, TwoLevelsJoinedByAStairwell) {
  // Two storeys of one 6 x 4 m outline; the stairwell [4.5, 6] x [0, 1.5] has no ceiling below and
  // no floor above.
  json walls = json::array();
  cells_rectangle(walls, 0, 0, 6, 4);
  json upper = json::array();
  cells_rectangle(upper, 0, 0, 6, 4);
  for (json& w : walls) w["level"] = "ground";
  for (json& w : upper) w["level"] = "upper", w["base"] = 2.7, walls.push_back(w);
  const std::vector<std::array<double, 2>> around = {{0, 0}, {4.5, 0}, {4.5, 1.5}, {6, 1.5}, {6, 4}, {0, 4}};
  json ground_room = cells_room("ground", around),
       stairs = cells_room("stairs", {{4.5, 0}, {6, 0}, {6, 1.5}, {4.5, 1.5}});
  json upper_room = cells_room("upper", around);
  ground_room["level"] = "ground", stairs["level"] = "ground", stairs["ceiling"] = false;
  upper_room["level"] = "upper";
  const json levels = {{{"id", "ground"}, {"elevation", 0.0}, {"height", 2.5}},
                       {{"id", "upper"}, {"elevation", 2.7}, {"height", 2.5}}};
  const PreparedScene s =
      cells_scene({{"levels", levels}, {"walls", walls}, {"rooms", {ground_room, stairs, upper_room}}});
  const SceneCells& cells = *s.cells;
  EXPECT_EQ(cells.bands.size(), 2u);
  EXPECT_EQ(cells.cells.size(), 4u);  // the outside, the ground floor's room and stairwell, the upper room
  const uint32_t ground = room_cell(s, "ground"), well = room_cell(s, "stairs"), top = room_cell(s, "upper");
  ASSERT_NE(ground, no_cell);
  ASSERT_NE(well, no_cell);
  ASSERT_NE(top, no_cell);
  // Up out of the stairwell through its missing ceiling, into the upper room through its missing floor.
  auto shapes = [&](uint32_t from, uint32_t to, PortalKind kind) {
    uint32_t n = 0;
    for (const Portal& p : cells.portals) n += p.from == from && p.to == to && p.kind == kind ? p.count : 0;
    return n;
  };
  EXPECT_GT(shapes(well, 0, PortalKind::ceiling), 0u);
  EXPECT_GT(shapes(0, top, PortalKind::floor), 0u);
  // From the ground floor looking up the stairwell the upper room is reached; looking at a wall, not.
  EXPECT_TRUE(cells_reached(cells, {2.0, 1.6, 2.5}, {5.25, 4.5, 0.75})[top]);
  EXPECT_FALSE(cells_reached(cells, {2.0, 1.6, 2.5}, {0.0, 1.2, 2.5})[top]);
  EXPECT_FALSE(cells_reached(cells, {1.0, 1.6, 3.0}, {1.2, 5.0, 3.2})[top]);  // up at the ground's ceiling
  EXPECT_TRUE(cells_reached(cells, {1.0, 1.6, 3.0}, {1.2, 5.0, 3.2})[ground]);
  // Seen from above with ceilings left out (ceilings: auto), the outside sees down into every room.
  const std::vector<uint8_t> above = cells_reached(cells, {3.0, 12.0, 2.0}, {3.0, 0.0, 2.1});
  EXPECT_TRUE(above[0] && above[top]);
}

TEST(Cells, WallsThatDoNotCloseAreOneCell) {
  json walls = json::array();
  cells_rectangle(walls, 0, 0, 6, 4);
  walls.erase(walls.begin() + 2);  // a U: the inside reaches the outside
  const PreparedScene open =
      cells_scene({{"walls", walls}, {"rooms", {cells_room("A", {{0, 0}, {6, 0}, {6, 4}, {0, 4}})}}});
  EXPECT_FALSE(open.cells->derived());
  EXPECT_EQ(open.cells->cells.size(), 1u);
  EXPECT_TRUE(open.cells->portals.empty());
  // No walls at all (a soup of solids): one cell likewise.
  const json box = {{"type", "box"}, {"center", {0, 0}}, {"size", {1, 1, 1}}};
  EXPECT_FALSE(cells_scene({{"solids", {box}}}).cells->derived());
  // Walls that close without rooms: the space they enclose is a cell.
  json closed = json::array();
  cells_rectangle(closed, 0, 0, 6, 4);
  const PreparedScene walled = cells_scene({{"walls", closed}});
  EXPECT_EQ(walled.cells->cells.size(), 2u);
  EXPECT_EQ(walled.cells->cells[1].room, -1);
}

// The nine homes: their cells against their rooms. Each enclosed space of a level is a cell, split
// along the boundaries of the rooms in it that hold 1 m^2 or more of it; so a room that closes (its
// walls reach floor to ceiling all round, its openings aside) labels a cell of its own. The counts
// are the ones docs/culling.md quotes: <room> elements, cells (the outside included), rooms that
// label a cell. A home's rooms that label none lie in one walled space with a larger room, are
// smaller than 1 m^2, or are not closed by walls (a mezzanine, a terrace).
struct HomeCells {
  const char* home;
  size_t room_elements, cells, rooms_labelled;
};
constexpr HomeCells nine_homes[] = {{"1BedroomApartmentWithRoundWall", 3, 4, 3},
                                    {"2BedroomApartment", 7, 10, 7},
                                    {"2BedroomApartmentWithBowWindow", 8, 11, 8},
                                    {"2BedroomHouseWithBasement", 13, 14, 11},
                                    {"3BedroomApartment", 8, 10, 8},
                                    {"3BedroomHouseWithAttic", 11, 11, 8},
                                    {"3BedroomHouseWithMezzanine", 23, 10, 7},
                                    {"4BedroomHouse", 11, 14, 10},
                                    {"Studio", 5, 5, 4}};

TEST(Cells, NineHomesCellsAgainstTheirRooms) {
  const std::optional<std::filesystem::path> data = testing::shared_data_dir();
  const std::filesystem::path dir = data ? *data / "floorplans" / "sweethome3d" : std::filesystem::path();
  if (!data || !std::filesystem::is_directory(dir)) GTEST_SKIP() << "no homes (../shared/data absent)";
  std::vector<std::filesystem::path> homes;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() == ".xml") homes.push_back(e.path());
  }
  std::sort(homes.begin(), homes.end());
  ASSERT_EQ(homes.size(), 9u);
  for (const std::filesystem::path& home : homes) {
    const std::string xml = testing::read_file(home);
    size_t room_elements = 0;
    for (size_t at = xml.find("<room "); at != std::string::npos; at = xml.find("<room ", at + 1)) ++room_elements;
    ImportOptions options;
    options.furniture_models = false;  // cells come from walls, rooms and levels
    const RenderRequest request = request_from_json(import_path(home, std::nullopt, options).request);
    const PreparedScene s = prepare_scene(request.scene);
    const SceneCells& cells = *s.cells;
    const double start = testing::thread_cpu_ms();
    const SceneCells again = build_cells(s.scene.geometry, s.soup, *s.hierarchy);
    const double build_ms = testing::thread_cpu_ms() - start;
    EXPECT_EQ(again.cells.size(), cells.cells.size()) << home << ": deterministic";
    EXPECT_EQ(again.undirected_portals, cells.undirected_portals) << home;
    std::set<int> labels;
    size_t unlabelled = 0;
    for (size_t c = 1; c < cells.cells.size(); ++c) {
      if (cells.cells[c].room >= 0) labels.insert(cells.cells[c].room);
      else ++unlabelled;
    }
    std::map<PortalKind, size_t> kinds;
    for (const Portal& p : cells.portals) kinds[p.kind] += p.from < p.to;
    std::cout << home.stem().string() << ": " << room_elements << " <room>, " << cells.cells.size()
              << " cells (outside included) on " << cells.bands.size() << " bands, " << cells.undirected_portals
              << " portals (" << kinds[PortalKind::opening] << " openings, " << kinds[PortalKind::boundary]
              << " boundaries, " << kinds[PortalKind::floor] + kinds[PortalKind::ceiling] << " floors and ceilings, "
              << kinds[PortalKind::seam] << " seams), " << labels.size() << " rooms labelled, " << unlabelled
              << " unlabelled; built in " << build_ms << " ms of CPU, " << cells.bytes() / 1024 << " KiB\n";
    ASSERT_TRUE(cells.derived()) << home;
    const auto expected = std::find_if(std::begin(nine_homes), std::end(nine_homes),
                                       [&](const HomeCells& h) { return home.stem().string() == h.home; });
    ASSERT_NE(expected, std::end(nine_homes)) << home;
    EXPECT_EQ(room_elements, expected->room_elements) << home;
    EXPECT_EQ(cells.cells.size(), expected->cells) << home;
    EXPECT_EQ(labels.size(), expected->rooms_labelled) << home;
    // Every cell holds squares of at most one room label, and the labels are rooms of the scene.
    for (int r : labels) EXPECT_LT(size_t(r), request.scene.geometry.rooms.size()) << home;
  }
}

}  // namespace
}  // namespace rr
