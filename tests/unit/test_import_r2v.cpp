// R2V import: a hand-made plan (pixels -> metres at the default and a given scale, a door on an
// inner wall, a window on the outer wall, an opening clamped to its wall, a fixture box), errors
// naming the line, and the twenty plans of ../shared/data: one's counts against its lines, all of
// them imported and rendered with every pipeline.
#include "import_test_util.hpp"
#include "render/import/import.hpp"

#include <gtest/gtest.h>

#include <sstream>

namespace {

using nlohmann::json;
using rr::ImportResult;
using rr::InputError;

// A 200 x 100 px box split by an inner wall at x = 100; one opening on the inner wall, one on the
// outer wall at the top, one reaching 10 px past the right wall's end.
const char* small_plan =
    "0\t0\t200\t0\twall\t1\t1\n"
    "200\t0\t200\t100\twall\t1\t1\n"
    "200\t100\t0\t100\twall\t1\t1\n"
    "0\t100\t0\t0\twall\t1\t1\n"
    "100\t0\t100\t100\twall\t1\t1\n"
    "100\t30\t100\t66\tdoor\t1\t1\n"
    "140\t0\t180\t0\tdoor\t2\t1\n"
    "200\t70\t200\t110\tdoor\t3\t1\n"
    "10\t10\t40\t60\tbathtub\t1\t2\n"
    "50\t50\t60\t60\tbedroom\t1\t1\n";

TEST(ImportR2v, SmallPlanAtTheDefaultScale) {
  ImportResult r = rr::import_r2v(small_plan);
  const json& walls = r.request["scene"]["walls"];
  ASSERT_EQ(walls.size(), 5u);
  EXPECT_EQ(walls[1]["start"], json::array({5.0, 0.0}));  // 200 px * 0.025 m
  EXPECT_EQ(walls[1]["end"], json::array({5.0, 2.5}));
  // The inner wall's opening has rooms on both sides: a doorway 0.75 m from the wall's start.
  ASSERT_EQ(walls[4]["openings"].size(), 1u);
  const json& door = walls[4]["openings"][0];
  EXPECT_EQ(door["type"], "door");
  EXPECT_DOUBLE_EQ(door["offset"].get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(door["width"].get<double>(), 0.9);
  // The top wall's opening faces the outside: a window.
  ASSERT_EQ(walls[0]["openings"].size(), 1u);
  EXPECT_EQ(walls[0]["openings"][0]["type"], "window");
  EXPECT_DOUBLE_EQ(walls[0]["openings"][0]["offset"].get<double>(), 3.5);
  // 70..110 px on a wall ending at 100 px: clamped to 30 px, with a warning naming line 8.
  ASSERT_EQ(walls[1]["openings"].size(), 1u);
  EXPECT_DOUBLE_EQ(walls[1]["openings"][0]["width"].get<double>(), 0.75);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0], "line 8: door reaches past its wall's end; clamped");
  // The bathtub icon is a box; the room label is not drawn.
  const json& solids = r.request["scene"]["solids"];
  ASSERT_EQ(solids.size(), 1u);
  EXPECT_EQ(solids[0]["center"], json::array({0.625, 0.875}));
  EXPECT_EQ(solids[0]["size"], json::array({0.75, 0.55, 1.25}));
  // Tiles of 0.5 m over the 5 x 2.5 m extent.
  EXPECT_EQ(r.request["scene"]["floor"]["cells"], json::array({10, 5}));
  EXPECT_NO_THROW(rr::request_from_json(r.request));
  EXPECT_GT(rr::testing::covered_share(r.request, "zbuffer"), 0.2);
}

TEST(ImportR2vScale, GivenScaleMultipliesEveryCoordinate) {
  rr::ImportOptions options;
  options.scale = 0.01;
  ImportResult r = rr::import_r2v(small_plan, options);
  EXPECT_EQ(r.request["scene"]["walls"][1]["end"], json::array({2.0, 1.0}));
  options.scale = -1.0;
  EXPECT_THROW(rr::import_r2v(small_plan, options), InputError);
}

TEST(ImportR2v, BadLinesNameTheirLine) {
  try {
    rr::import_r2v("0\t0\t10\t0\twall\n0\tx\t10\t0\twall\n");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer(), "/line/2");
    EXPECT_EQ(std::string(e.what()), "line 2: coordinate 'x' is not a number");
  }
  try {
    rr::import_r2v("0\t0\t10\n");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.pointer(), "/line/1");
  }
  EXPECT_THROW(rr::import_r2v("1\t1\t5\t5\tbedroom\n"), InputError);  // no walls at all
}

// Counts of each category in an R2V file, read line by line here rather than by the importer.
std::map<std::string, size_t> category_counts(const std::string& text) {
  std::map<std::string, size_t> counts;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::string x1, y1, x2, y2, category;
    if (fields >> x1 >> y1 >> x2 >> y2 >> category) ++counts[category];
  }
  return counts;
}

TEST(ImportR2v, FirstRealPlanHasItsWallsAndOpenings) {
  auto files = rr::testing::shared_files("floorplans/r2v", ".txt", "r2v_");
  if (files.empty()) GTEST_SKIP() << "../shared/data is absent";
  std::string text = rr::testing::read_file(files.front());
  auto counts = category_counts(text);
  ImportResult r = rr::import_r2v(text);
  const json& walls = r.request["scene"]["walls"];
  EXPECT_EQ(walls.size(), counts["wall"]);
  EXPECT_EQ(walls.size(), 10u);  // SOURCES.md's table
  size_t openings = 0;
  for (const json& w : walls) openings += w["openings"].size();
  EXPECT_EQ(openings, counts["door"]);
  EXPECT_EQ(openings, 6u);
  EXPECT_TRUE(r.warnings.empty());
}

class R2vPlan : public ::testing::TestWithParam<std::filesystem::path> {};

TEST_P(R2vPlan, ImportsAndRendersWithEveryPipeline) {
  std::string text = rr::testing::read_file(GetParam());
  ImportResult r = rr::import_r2v(text);
  EXPECT_EQ(r.request["scene"]["walls"].size(), category_counts(text)["wall"]);
  for (const std::string& pipeline : rr::testing::pipeline_names()) {
    // The default camera frames the plan's bounding sphere from above: a long narrow plan fills
    // less than a fifth of the frame, but never nothing.
    EXPECT_GT(rr::testing::covered_share(r.request, pipeline), 0.1) << pipeline;
  }
}

INSTANTIATE_TEST_SUITE_P(SharedData, R2vPlan,
                         ::testing::ValuesIn(rr::testing::shared_files("floorplans/r2v", ".txt", "r2v_")),
                         [](const auto& param_info) { return rr::testing::test_name_of(param_info.param); });
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(R2vPlan);

}  // namespace
