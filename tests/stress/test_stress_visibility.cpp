// Visibility against the exact reference on seeded random rooms and object soups: zbuffer, bsp and
// painter-newell must give the reference's id at every pixel off the reference's id edges;
// painter mean/min errors are measured and printed, not asserted. Also the depth precision claim of
// docs/accuracy.md: two surfaces 1 mm apart at 10 m, default near/far, resolve exactly.
#include "stress/stress_support.hpp"

#include <cstdio>
#include <map>

namespace rr::stress {
namespace {

struct Tally {
  size_t scenes = 0, pixels = 0, differing = 0;
  double worst = 0.0;
  void add(const VisibilityError& e) {
    ++scenes;
    pixels += e.non_edge_pixels;
    differing += e.non_edge_differing;
    worst = std::max(worst, e.non_edge_share());
  }
};

// Non-edge pixels of the truth where `test` shows another polygon at that one pixel only (its four
// neighbours in `test` are the truth's id). Two causes, both sub-pixel snapping (docs/accuracy.md):
// a polygon corner that covers a single pixel centre by less than half a sub-pixel unit (the snapped corner
// covers it or not; the reference sees only that pixel, so it is no edge there), and in BSP a crack
// at a T-junction between fragments of one polygon (a fragment split again gets a vertex its
// sibling lacks, snapped on its own).
size_t count_pinholes(const IdBuffer& truth, const IdBuffer& test) {
  size_t n = 0;
  for (int y = 1; y + 1 < truth.height; ++y) {
    for (int x = 1; x + 1 < truth.width; ++x) {
      const uint32_t id = truth.at(x, y);
      if (test.at(x, y) == id || is_edge_pixel(truth, x, y)) continue;
      n += test.at(x - 1, y) == id && test.at(x + 1, y) == id && test.at(x, y - 1) == id && test.at(x, y + 1) == id;
    }
  }
  return n;
}

void check_visible_scenes(const char* what, unsigned first_seed, unsigned count, json (*make)(std::mt19937&)) {
  const auto seeds = testing::test_seeds(first_seed, count);
  Tally mean, min;
  std::map<std::string, size_t> cracks;
  size_t non_edge_pixels = 0;
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    std::mt19937 rng(seed);
    const StressScene scene(make(rng));
    const Frame truth = scene.render("reference");
    for (const PipelineInfo* p : testing::exact_pipelines(false)) {
      const Frame frame = scene.render_exact(*p);
      const VisibilityError e = visibility_error(truth.ids, frame.ids);
      const size_t pinholes = count_pinholes(truth.ids, frame.ids);
      cracks[p->name] += pinholes;
      EXPECT_EQ(e.non_edge_differing - pinholes, 0u)
          << what << " " << seed_note(seed) << ": " << p->name << " differs at " << e.non_edge_differing << " of "
          << e.non_edge_pixels << " non-edge pixels, " << pinholes << " of them pinholes";
      non_edge_pixels += e.non_edge_pixels;
    }
    mean.add(visibility_error(truth.ids, scene.render("painter", PainterKey::mean).ids));
    min.add(visibility_error(truth.ids, scene.render("painter", PainterKey::min).ids));
  }
  // Pinholes (see count_pinholes) are bounded, not zero: at most 1 per 10^4 non-edge pixels.
  for (const auto& [name, n] : cracks) {
    std::printf("[stress] %s %s: %zu pinhole pixels\n", what, name.c_str(), n);
    EXPECT_LE(double(n), 1e-4 * double(non_edge_pixels / testing::exact_pipelines(false).size())) << name;
  }
  for (auto [name, t] : {std::pair{"painter-mean", mean}, std::pair{"painter-min", min}}) {
    std::printf("[stress] %s %s: non-edge visibility error %.5f%% over %zu scenes (worst scene %.4f%%)\n", what, name,
                t.pixels ? 100.0 * double(t.differing) / double(t.pixels) : 0.0, t.scenes, 100.0 * t.worst);
  }
}

TEST(StressVisibility, RandomRoomsMatchTheReferenceAwayFromEdges) {
  check_visible_scenes("rooms", 1000, 48, random_room);
}

TEST(StressVisibility, RandomIntersectingSoupsMatchTheReferenceAwayFromEdges) {
  check_visible_scenes("soups", 2000, 48, [](std::mt19937& rng) { return random_soup(rng, 40); });
}

// A random room with `count` sliver triangles hung in it: each 0.1 to 0.6 m long, 1 to 5 um wide and
// wholly at least 0.6 m from the eye. At 640 x 480 and the rooms' vertical fields of view (50 to 90
// degrees) a pixel there spans at least 1.17 mm, so every sliver is thinner than 1/200 pixel: it
// covers a pixel centre only where the centre lies within that width of its axis.
json sliver_room(std::mt19937& rng, int count) {
  json request = random_room(rng);
  request["options"]["width"] = 640;
  request["options"]["height"] = 480;
  const json& eye_json = request["camera"]["position"];
  const Vec3 eye(eye_json[0].get<double>(), eye_json[1].get<double>(), eye_json[2].get<double>());
  double w = 0.0, d = 0.0, h = 0.0;
  for (const json& wall : request["scene"]["walls"]) {
    w = std::max(w, wall["end"][0].get<double>()), d = std::max(d, wall["end"][1].get<double>());
    h = wall["height"].get<double>();
  }
  json vertices = json::array(), faces = json::array();
  while (int(faces.size()) < count) {
    const Vec3 c(uniform(rng, 0.2, w - 0.2), uniform(rng, 0.1, h - 0.1), uniform(rng, 0.2, d - 0.2));
    const double half = uniform(rng, 0.05, 0.3), width = uniform(rng, 1e-6, 5e-6);
    if (glm::length(c - eye) < 0.6 + half) continue;
    // A random axis and a random direction across it.
    const double theta = uniform(rng, 0, 2 * pi), z = uniform(rng, -1, 1), r = std::sqrt(1 - z * z);
    const Vec3 axis(r * std::cos(theta), z, r * std::sin(theta));
    const Vec3 across = glm::normalize(glm::cross(axis, std::abs(axis.y) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0)));
    const Vec3 p[3] = {c - half * axis, c + half * axis, c + uniform(rng, -0.5, 0.5) * half * axis + width * across};
    const size_t first = vertices.size();
    for (const Vec3& v : p) vertices.push_back({v.x, v.y, v.z});
    faces.push_back({first, first + 1, first + 2});
  }
  request["scene"]["solids"].push_back({{"type", "mesh"}, {"vertices", vertices}, {"faces", faces}});
  return request;
}

TEST(StressVisibility, SliverRoomsMatchTheReferenceWithinTwoIn100000AwayFromEdges) {
  // Vertex snapping is the only thing between the rasterizers' coverage and the reference's exact
  // projection. A sliver far thinner than a pixel shows where it moves coverage most: a snapped
  // sliver covers the centres within its own width of where the snapped vertices put it, so the
  // share of pixels that differ off the reference's id edges grows with the snapping step.
  const auto seeds = testing::test_seeds(5000, 8);
  for (const PipelineInfo* p : testing::exact_pipelines(false)) {
    size_t pixels = 0, differing = 0;
    double worst = 0.0;
    unsigned worst_seed = 0;
    for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
      std::mt19937 rng(seed);
      const StressScene scene(sliver_room(rng, 3000));
      const Frame truth = scene.render("reference");
      const RenderResult run = scene.run_exact(*p);
      const Frame& frame = run.frame;
      ASSERT_FALSE(run.stats.painter_budget_exhausted) << p->name << " " << seed_note(seed);
      const VisibilityError e = visibility_error(truth.ids, frame.ids);
      EXPECT_LE(e.non_edge_share(), 2e-5) << p->name << " " << seed_note(seed) << ": " << e.non_edge_differing << " of "
                                          << e.non_edge_pixels << " non-edge pixels differ";
      pixels += e.non_edge_pixels, differing += e.non_edge_differing;
      if (e.non_edge_share() > worst) worst = e.non_edge_share(), worst_seed = seed;
    }
    const double share = double(differing) / double(pixels);
    std::printf("[stress] slivers %s: %zu of %zu non-edge pixels differ (%.2e; worst scene %.2e, seed %u)\n", p->name,
                differing, pixels, share, worst, worst_seed);
    EXPECT_LE(share, 2e-5) << p->name << ": worst " << seed_note(worst_seed);
  }
}

TEST(StressVisibility, ZbufferResolvesOneMillimetreAtTenMetres) {
  // Two parallel 4 m squares facing the camera at 10 m and 10.001 m view depth, the nearer one
  // half the size and drawn second (so a depth tie would keep the farther one): with the default
  // near 0.1 and far 100 every covered non-edge pixel must show the nearer square, like the
  // reference. 1/w differs by 1e-5 relative there; float has 6e-8.
  for (bool near_first : {false, true}) {
    const json far_quad = {{{-2, -2, -10.001}, {2, -2, -10.001}, {2, 2, -10.001}, {-2, 2, -10.001}}};
    const json near_quad = {{{-1, -1, -10.0}, {1, -1, -10.0}, {1, 1, -10.0}, {-1, 1, -10.0}}};
    json solids = json::array();
    for (const json& q : near_first ? json{near_quad, far_quad} : json{far_quad, near_quad}) {
      solids.push_back({{"type", "mesh"}, {"vertices", q[0]}, {"faces", {{0, 1, 2, 3}}}});
    }
    const StressScene scene({{"scene", {{"solids", solids}}},
                             {"camera", {{"position", {0, 0, 0}}, {"target", {0, 0, -1}}, {"fov_y", 30}}},
                             {"options", {{"width", 200}, {"height", 200}}}});
    const Frame truth = scene.render("reference"), z = scene.render("zbuffer");
    const uint32_t near_id = near_first ? 0 : 1;
    size_t near_pixels = 0;
    for (uint32_t id : truth.ids.ids) near_pixels += id == near_id;
    EXPECT_GT(near_pixels, 3000u);
    EXPECT_EQ(visibility_error(truth.ids, z.ids).non_edge_differing, 0u) << "near square drawn first: " << near_first;
  }
}

}  // namespace
}  // namespace rr::stress
