// The per-pixel kernels give the same bytes at every SIMD level this CPU runs: each loop against a
// plain scalar loop on seeded random spans, and every example drawn by every pipeline, shading and
// shadows setting with each level forced, against the baseline level.
#include "render/core/kernels.hpp"
#include "render/core/png.hpp"
#include "render/core/polygon_ops.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/render_modes.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <random>
#include <vector>

namespace rr {
namespace {

// Restores the process's kernel set when a test ends.
struct ForcedKernels {
  const char* before = kernels().name;
  ~ForcedKernels() { use_kernels(before); }
};

struct Span {
  double z0, dz;
  int n;
  std::vector<float> depth;
  std::vector<uint32_t> visible, group_of;
};

Span random_span(std::mt19937& rng) {
  std::uniform_real_distribution<double> z(0.01, 2.0), slope(-1e-3, 1e-3);
  std::uniform_int_distribution<int> length(0, 300), pick(0, 7);
  Span s{z(rng), slope(rng), length(rng), {}, {}, {}};
  s.group_of = {0, 3, 3, 5, 0, 3, 7, 5};
  for (int i = 0; i < s.n; ++i) {
    // Ties included: depths equal to the span's own values test the strict comparison.
    const int kind = pick(rng);
    s.depth.push_back(kind == 0 ? 0.0f : kind == 1 ? float(s.z0 + double(i) * s.dz) : float(z(rng)));
    s.visible.push_back(kind == 0 ? no_visible : uint32_t(pick(rng)));
  }
  return s;
}

// The floats' bit patterns, so that equal values of different sign or payload still differ.
std::vector<uint32_t> bits(const std::vector<float>& values) {
  std::vector<uint32_t> out;
  for (float v : values) out.push_back(std::bit_cast<uint32_t>(v));
  return out;
}

TEST(Kernels, EveryLevelMatchesAScalarLoopBitForBit) {
  ASSERT_FALSE(available_kernels().empty());
  EXPECT_STREQ(available_kernels().front()->name, "sse2");
  const unsigned seed = std::random_device{}();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937 rng(seed);
  for (int trial = 0; trial < 500; ++trial) {
    const Span s = random_span(rng);
    const uint32_t group = trial % 2 ? 3u : 5u;
    Span plain = s, grouped = s;
    for (int i = 0; i < s.n; ++i) {  // the scalar definitions of kernels.hpp
      const float z = float(s.z0 + double(i) * s.dz);
      if (z > plain.depth[i]) plain.depth[i] = z, plain.visible[i] = 99;
      const uint32_t v = grouped.visible[i];
      const bool same_plane = v != no_visible && s.group_of[v] == group;
      if (!same_plane && z > grouped.depth[i]) grouped.depth[i] = z, grouped.visible[i] = 99;
    }
    for (const Kernels* k : available_kernels()) {
      SCOPED_TRACE(k->name);
      Span a = s, b = s;
      k->depth_span(s.z0, s.dz, s.n, 99, a.depth.data(), a.visible.data());
      k->grouped_depth_span(s.z0, s.dz, s.n, 99, group, s.group_of.data(), b.depth.data(), b.visible.data());
      ASSERT_EQ(bits(a.depth), bits(plain.depth));
      ASSERT_EQ(a.visible, plain.visible);
      ASSERT_EQ(bits(b.depth), bits(grouped.depth));
      ASSERT_EQ(b.visible, grouped.visible);
    }
  }
}

TEST(Kernels, SplitterClassificationMatchesPlaneDistanceAtEveryLevel) {
  const unsigned seed = std::random_device{}();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coordinate(-50.0, 50.0), unit(-1.0, 1.0);
  std::uniform_int_distribution<int> rows_of(1, 6), length(0, int(classify_block)), pick(0, 3);
  size_t on = 0, spanning = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int rows = rows_of(rng), n = length(rng), stride = n + 3;
    const Vec3 normal = glm::normalize(Vec3(unit(rng), unit(rng), unit(rng)) + Vec3(1e-9));
    const Plane plane{normal, coordinate(rng)};
    const double epsilon = trial % 3 ? 1e-6 : 0.5;
    std::vector<double> x(size_t(rows * stride)), y(x.size()), z(x.size());
    for (size_t i = 0; i < x.size(); ++i) {
      Vec3 p(coordinate(rng), coordinate(rng), coordinate(rng));
      // A quarter of the points within epsilon of the plane or on its edge: the strict comparisons.
      const int kind = pick(rng);
      if (kind == 0) p -= (plane.distance(p) - epsilon * unit(rng)) * normal;
      if (kind == 1) p -= (plane.distance(p) - epsilon) * normal;
      x[i] = p.x, y[i] = p.y, z[i] = p.z;
    }
    std::vector<uint8_t> want(size_t(n), 0);
    size_t want_counts[4] = {7, 0, 3, 1};  // accumulated into, as the splitter's running counts are
    for (int k = 0; k < rows; ++k) {
      for (int i = 0; i < n; ++i) {
        const size_t at = size_t(k * stride + i);
        const double d = plane.distance(Vec3(x[at], y[at], z[at]));  // the definition
        want[size_t(i)] |= uint8_t((d > epsilon ? 1 : 0) | (d < -epsilon ? 2 : 0));
      }
    }
    for (uint8_t v : want) ++want_counts[v];
    on += size_t(std::count(want.begin(), want.end(), 0));
    spanning += size_t(std::count(want.begin(), want.end(), 3));
    const double coefficients[4] = {plane.normal.x, plane.normal.y, plane.normal.z, plane.offset};
    for (const Kernels* k : available_kernels()) {
      SCOPED_TRACE(k->name);
      std::vector<uint8_t> side(size_t(n), 0xAB);
      size_t counts[4] = {7, 0, 3, 1};
      k->classify_points(x.data(), y.data(), z.data(), size_t(stride), size_t(rows), size_t(n), coefficients, epsilon,
                         side.data(), counts);
      ASSERT_EQ(side, want) << "trial " << trial;
      for (int v = 0; v < 4; ++v) ASSERT_EQ(counts[v], want_counts[v]) << "side " << v << ", trial " << trial;
    }
  }
  EXPECT_GT(on, 1000u);
  EXPECT_GT(spanning, 1000u);
}

TEST(Kernels, EveryExampleIsByteIdenticalAtEveryLevel) {
  ForcedKernels restore;
  std::printf("kernel levels on this CPU:");
  for (const Kernels* k : available_kernels()) std::printf(" %s", k->name);
  std::printf("\n");
  size_t compared = 0;
  for (const auto& file : testing::example_files()) {
    nlohmann::json j = nlohmann::json::parse(testing::read_file(file));
    j["options"]["width"] = 250;
    j["options"]["height"] = 170;
    testing::for_each_render_mode(j, false, [&](const nlohmann::json& mode, const std::string& label) {
      SCOPED_TRACE(file.filename().string() + label);
      const RenderRequest request = request_from_json(mode);
      const PolygonSoup soup = tessellate(request.scene.geometry);
      std::string baseline_png;
      std::vector<uint32_t> baseline_ids;
      for (const Kernels* k : available_kernels()) {
        ASSERT_TRUE(use_kernels(k->name));
        RenderContext context;
        context.threads = 2;
        RenderResult r = render_frame(request.scene, soup, request.camera, request.options, context);
        std::string png = encode_png(r.frame.image);
        if (k == available_kernels().front()) {
          baseline_png = std::move(png), baseline_ids = std::move(r.frame.ids.ids);
          continue;
        }
        EXPECT_TRUE(png == baseline_png) << k->name << ": the PNG differs from sse2's";
        EXPECT_TRUE(r.frame.ids.ids == baseline_ids) << k->name << ": the id buffer differs from sse2's";
        ++compared;
      }
    });
  }
  if (available_kernels().size() == 1) GTEST_SKIP() << "this CPU runs only the baseline level";
  EXPECT_GT(compared, 0u);
}

}  // namespace
}  // namespace rr
