// The same room and soup moved by 1, 1e3, 1e5, 1e6 and 1e7 m (the coordinate limit) and scaled by 1e-3 .. 1e3
// (geometry, camera, lights and near/far together): every pipeline sees the same polygon at every pixel off the
// untransformed reference's id edges, no value anywhere is NaN or infinite, the BSP build terminates and its fragments
// conserve each polygon's area to 1e-9 relative (moved or scaled; both at once is bounded by the input's own rounding,
// see below); with shadows on, every pipeline's shadow mask is the one it has at the origin, off shadow edges.
#include "render/pipelines/bsp.hpp"
#include "stress/stress_support.hpp"

#include <cstdio>
#include <map>

namespace rr::stress {
namespace {

const double kOffsets[] = {0.0, 1.0, 1e3, 1e5, 1e6, 1e7};
const double kScales[] = {1e-3, 1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3};

bool all_finite(const PolygonSoup& soup) {
  for (const Vec3& p : soup.positions) {
    if (!is_finite(p)) return false;
  }
  for (const glm::vec3& n : soup.normals) {
    if (!std::isfinite(n.x) || !std::isfinite(n.y) || !std::isfinite(n.z)) return false;
  }
  for (const Polygon& p : soup.polygons) {
    if (!is_finite(p.normal) || !std::isfinite(p.offset)) return false;
  }
  return true;
}

// Largest relative difference between a polygon's area and the sum of its fragments' areas.
double worst_area_error(const PolygonSoup& soup, const BspTree& tree) {
  std::map<uint32_t, double> pieces;
  for (const Polygon& f : tree.fragments.polygons) pieces[f.id] += polygon_area(tree.fragments.points(f));
  double worst = 0.0;
  for (const Polygon& p : soup.polygons) {
    const double area = polygon_area(soup.points(p));
    worst = std::max(worst, std::abs(pieces[p.id] - area) / area);
  }
  return worst;
}

void check_placements(const json& request, const std::string& what) {
  const StressScene base(request);
  const Frame truth = base.render("reference");
  for (double offset : kOffsets) {
    for (double scale : kScales) {
      if (offset != 0.0 && scale != 1.0 && scale != 1e-3 && scale != 1e3) continue;  // the corners suffice
      SCOPED_TRACE(what + " scaled by " + std::to_string(scale) + ", moved by " + std::to_string(offset) + " m");
      StressScene moved(request);
      moved.place(scale, Vec3(offset, 0.5 * offset, -offset));
      ASSERT_TRUE(all_finite(moved.soup));
      const BspTree tree = build_bsp(moved.soup, moved.request.options.bsp);
      EXPECT_TRUE(all_finite(tree.fragments));
      // 1e-9 for a move alone up to 1e6 m or a scaling alone. The spacing of doubles, and with it
      // the rounding of every vertex and cut, grows with the offset: 1e-8 at 1e7 m (1.9e-9 m apart,
      // measured up to 3.5e-9 there). Both at once (a 5 mm room 1e6 m away) puts the input itself
      // further past that: doubles there are 1.2e-10 m apart, 2.4e-8 of the room, so the bound is
      // that rounding times the polygons' size ratio; the value is printed.
      const double area_error = worst_area_error(moved.soup, tree);
      if (offset == 0.0 || scale == 1.0) {
        EXPECT_LE(area_error, 1e-9 * std::max(1.0, offset / 1e6));
      } else {
        std::printf("[stress] %s: scale %.0e and offset %.0e m together: BSP area error %.2e\n", what.c_str(), scale,
                    offset, area_error);
        EXPECT_LE(area_error, 1e-5);
      }
      for (const PipelineInfo* pipeline : testing::exact_pipelines()) {
        const Frame f = moved.render_exact(*pipeline);
        const VisibilityError e = visibility_error(truth.ids, f.ids);
        EXPECT_EQ(e.non_edge_differing, 0u)
            << pipeline->name << ": " << e.non_edge_differing << " non-edge pixels differ";
      }
    }
  }
}

// Pixels whose shadow mask differs between a and b, away from a's shadow edges (a 4-neighbour
// with another mask).
size_t mask_differences_off_edges(const Frame& a, const Frame& b) {
  const int w = a.image.width, h = a.image.height;
  size_t count = 0;
  for (int y = 1; y + 1 < h; ++y) {
    for (int x = 1; x + 1 < w; ++x) {
      const size_t i = size_t(y) * size_t(w) + size_t(x);
      const uint8_t m = a.shadow_mask[i];
      const bool edge = a.shadow_mask[i - 1] != m || a.shadow_mask[i + 1] != m || a.shadow_mask[i - size_t(w)] != m ||
                        a.shadow_mask[i + size_t(w)] != m;
      count += !edge && b.shadow_mask[i] != m;
    }
  }
  return count;
}

Frame render_shadowed(const StressScene& s, const PipelineInfo& pipeline) {
  RenderOptions options = testing::exact_options(pipeline, s.request.options);
  options.shadows = true;
  RenderContext context;
  context.shadow_mask = true;
  return render_frame(s.request.scene, s.soup, s.request.camera, options, context).frame;
}

// With shadows from the room's directional light and a point light, every pipeline's shadow mask
// (its shadow map, or the reference's exact rays) is the same at every offset as at the origin.
TEST(StressTransform, RoomKeepsItsShadowsWhenMoved) {
  const auto seeds = testing::test_seeds(3200, 2);
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    std::mt19937 rng(seed);
    json request = random_room(rng);
    request["scene"]["lights"].push_back({{"type", "point"}, {"position", {1.0, 2.2, 1.0}}});
    const StressScene base(request);
    for (const PipelineInfo* pipeline : testing::exact_pipelines()) {
      const Frame origin = render_shadowed(base, *pipeline);
      for (double offset : kOffsets) {
        if (offset == 0.0) continue;
        SCOPED_TRACE("room " + seed_note(seed) + ", " + pipeline->name + ", moved by " + std::to_string(offset) + " m");
        StressScene moved(request);
        moved.place(1.0, Vec3(offset, 0.5 * offset, -offset));
        const Frame f = render_shadowed(moved, *pipeline);
        EXPECT_EQ(visibility_error(origin.ids, f.ids).non_edge_differing, 0u);
        EXPECT_EQ(mask_differences_off_edges(origin, f), 0u);
      }
    }
  }
}

TEST(StressTransform, RoomKeepsItsVisibilityWhenMovedAndScaled) {
  const auto seeds = testing::test_seeds(3000, 2);
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    std::mt19937 rng(seed);
    check_placements(random_room(rng), "room " + seed_note(seed));
  }
}

TEST(StressTransform, SoupKeepsItsVisibilityWhenMovedAndScaled) {
  const auto seeds = testing::test_seeds(3100, 2);
  for (unsigned seed = seeds.first; seed < seeds.first + seeds.count; ++seed) {
    std::mt19937 rng(seed);
    check_placements(random_soup(rng, 30), "soup " + seed_note(seed));
  }
}

}  // namespace
}  // namespace rr::stress
