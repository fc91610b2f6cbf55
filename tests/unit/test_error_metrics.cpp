// Error measures on hand-made tiny buffers: edge pixels of an ASCII-art id buffer, visibility
// error over all and non-edge pixels, RMSE/PSNR by the stated formula, shadow-mask differences,
// size checks, the texture error's choice of pixels and the JSON shape `roomrender compare` prints.
#include "render/scene_io/measures_json.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <stdexcept>

namespace rr {
namespace {

// Rows of digits ('.' = background) -> an id buffer.
IdBuffer ids_from(const std::vector<std::string>& rows) {
  IdBuffer ids(int(rows[0].size()), int(rows.size()));
  for (int y = 0; y < ids.height; ++y) {
    for (int x = 0; x < ids.width; ++x) {
      const char c = rows[size_t(y)][size_t(x)];
      ids.ids[size_t(y * ids.width + x)] = c == '.' ? background_id : uint32_t(c - '0');
    }
  }
  return ids;
}

TEST(ErrorMetrics, EdgePixelsAreThoseWithAFourNeighbourOfAnotherId) {
  const IdBuffer ids = ids_from({"1111", "1122", "1122", "...."});
  const char* expected[] = {"0011", "0111", "1111", "1111"};  // diagonal neighbours do not count
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) EXPECT_EQ(is_edge_pixel(ids, x, y), expected[y][x] == '1') << x << "," << y;
  }
}

TEST(ErrorMetrics, VisibilityErrorCountsAllAndNonEdgePixels) {
  const IdBuffer truth = ids_from({"11111", "11111", "11122", "11122"});
  const IdBuffer test = ids_from({"11311", "11111", "11112", "11122"});
  // Differences at (2,0), an interior pixel of id 1, and (3,2), an edge pixel of the truth.
  const VisibilityError e = visibility_error(truth, test);
  EXPECT_EQ(e.pixels, 20u);
  EXPECT_EQ(e.differing, 2u);
  // Edge pixels of the truth: (3,1), (4,1) above the 2s, (2,2), (2,3) left of them, and (3,2),
  // (4,2), (3,3) inside the 2s; (4,3) is surrounded by 2s.
  EXPECT_EQ(e.non_edge_pixels, 20u - 7u);
  EXPECT_EQ(e.non_edge_differing, 1u);
  EXPECT_DOUBLE_EQ(e.share(), 0.1);
  EXPECT_DOUBLE_EQ(e.non_edge_share(), 1.0 / 13.0);
  EXPECT_EQ(visibility_error(truth, truth).differing, 0u);
  EXPECT_THROW(visibility_error(truth, ids_from({"1"})), std::invalid_argument);
}

TEST(ErrorMetrics, RmseAndPsnrFollowTheStatedFormula) {
  Image a(2, 1, Color(0.0f)), b(2, 1, Color(0.0f));
  b.rgb[4] = 3;  // one channel of six off by 3: RMSE = sqrt(9 / 6)
  const ShadingError e = shading_error(a, b);
  EXPECT_DOUBLE_EQ(e.rmse, std::sqrt(1.5));
  EXPECT_DOUBLE_EQ(e.psnr_db, 20.0 * std::log10(255.0 / std::sqrt(1.5)));
  b.rgb.assign(6, 255);  // every channel off by 255: RMSE 255, PSNR 0 dB
  EXPECT_DOUBLE_EQ(shading_error(a, b).rmse, 255.0);
  EXPECT_DOUBLE_EQ(shading_error(a, b).psnr_db, 0.0);
  EXPECT_TRUE(std::isinf(shading_error(a, a).psnr_db));
  EXPECT_THROW(shading_error(a, Image(1, 2, Color(0.0f))), std::invalid_argument);
}

// Polygons 1 and 2 are textured, 3 is not. Pixels counted: the reference shows 1 or 2 there, no
// 4-neighbour differs, and (with test ids) the test drew the same polygon.
TEST(ErrorMetrics, TextureErrorCountsTexturedPixelsAwayFromEdges) {
  const IdBuffer truth = ids_from({"11113", "11113", "1111.", "22222", "22222", "22222"});
  const std::vector<uint8_t> textured = {0, 1, 1, 0};
  // Counted: the 1s at x 0..2 of rows 0 and 1 (x 3 touches a 3, row 2 touches the 2s) and the 2s of
  // rows 4 and 5 (row 3 touches the 1s and the background): 6 + 10.
  Image ref(5, 6, Color(0.0f)), test(5, 6, Color(0.0f));
  test.rgb[size_t((1 * 5 + 1) * 3)] = 6;   // (1,1): counted, one channel off by 6
  test.rgb[size_t((3 * 5 + 3) * 3)] = 90;  // (3,3): an edge pixel of the 2s, not counted
  test.rgb[size_t((0 * 5 + 4) * 3)] = 90;  // (4,0): polygon 3, untextured
  TexturedPixelError e = texture_error(truth, textured, ref, test);
  EXPECT_EQ(e.pixels, 16u);
  EXPECT_DOUBLE_EQ(e.rmse, std::sqrt(36.0 / 48.0));
  EXPECT_DOUBLE_EQ(e.psnr_db, 20.0 * std::log10(255.0 / e.rmse));
  // The test drew polygon 3 over (1,1) and (0,5): both leave the count.
  IdBuffer drawn = truth;
  drawn.ids[size_t(1 * 5 + 1)] = 3;
  drawn.ids[size_t(5 * 5 + 0)] = 3;
  e = texture_error(truth, textured, ref, test, &drawn);
  EXPECT_EQ(e.pixels, 14u);
  EXPECT_EQ(e.rmse, 0.0);
  EXPECT_TRUE(std::isinf(e.psnr_db));
  EXPECT_EQ(textured_polygons(PolygonSoup{}).size(), 0u);
  const std::vector<uint8_t> too_few = {0, 1};  // id 2 and 3 are not in it
  EXPECT_THROW(texture_error(truth, too_few, ref, test), std::invalid_argument);
  EXPECT_THROW(texture_error(truth, textured, ref, Image(4, 6, Color(0.0f))), std::invalid_argument);
}

TEST(ErrorMetrics, ShadowErrorComparesWholeMaskBytes) {
  const std::vector<uint8_t> truth = {0, 1, 3, 2}, test = {0, 1, 1, 2};  // light 1 differs at one pixel
  const ShadowError e = shadow_error(truth, test);
  EXPECT_EQ(e.pixels, 4u);
  EXPECT_EQ(e.differing, 1u);
  EXPECT_DOUBLE_EQ(e.share(), 0.25);
  EXPECT_THROW(shadow_error(truth, std::vector<uint8_t>{0}), std::invalid_argument);
}

TEST(ErrorMetrics, ShadowErrorSplitsTheBandAroundShadowEdgesFromThePixelsAwayFromThem) {
  // 8 x 6 pixels, the reference lit (1) left of column 4 and shadowed (0) from it: its shadow edge
  // pixels are columns 3 and 4, the 2-pixel band columns 1 to 6, away columns 0 and 7.
  const int w = 8, h = 6;
  std::vector<uint8_t> truth(size_t(w * h)), test;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) truth[size_t(y * w + x)] = x < 4;
  test = truth;
  test[size_t(2 * w + 5)] = 1;  // in the band
  test[size_t(0 * w + 7)] = 1;  // away
  test[size_t(5 * w + 0)] = 0;  // away
  const ShadowError e = shadow_error(truth, test, 1, w);
  ASSERT_TRUE(e.split);
  EXPECT_EQ(e.differing, 3u);
  EXPECT_EQ(e.band_pixels, size_t(6 * h));
  EXPECT_EQ(e.away_pixels, size_t(2 * h));
  EXPECT_EQ(e.band_differing, 1u);
  EXPECT_EQ(e.away_differing, 2u);
  // A lone shadowed pixel in the middle of a 9 x 9 lit image: it and its 4-neighbours are edge pixels,
  // so the band is the 7 x 7 square around it less its 4 corners (3 pixels from each edge pixel
  // along one axis), and the image's corner pixel is away from it.
  std::vector<uint8_t> dot(81, 1), off = dot;
  dot[4 * 9 + 4] = 0;
  off[0] = 0;
  const ShadowError d = shadow_error(dot, off, 1, 9);
  EXPECT_EQ(d.band_pixels, 45u);
  EXPECT_EQ(d.away_differing, 1u);
  EXPECT_FALSE(shadow_error(dot, off).split);  // no width: no split
}

TEST(ErrorMetrics, CompareFramesAndJson) {
  Frame truth, test;
  truth.image = Image(2, 2, Color(0.5f));
  test.image = truth.image;
  truth.ids = ids_from({"11", "12"});
  test.ids = ids_from({"11", "11"});
  ErrorMeasures m = compare_frames(truth, test);
  EXPECT_FALSE(m.shadow.has_value());  // neither frame carries a mask
  nlohmann::json j = error_measures_json(m);
  EXPECT_EQ(j["width"], 2);
  EXPECT_EQ(j["visibility"]["differing"], 1);
  EXPECT_DOUBLE_EQ(j["visibility"]["error"].get<double>(), 0.25);
  EXPECT_EQ(j["shading"]["rmse"], 0.0);
  EXPECT_TRUE(j["shading"]["psnr_db"].is_null());  // infinite
  EXPECT_FALSE(j.contains("shadow"));
  truth.shadow_mask = {1, 1, 1, 0};
  test.shadow_mask = {1, 1, 1, 1};
  j = error_measures_json(compare_frames(truth, test));
  EXPECT_DOUBLE_EQ(j["shadow"]["error"].get<double>(), 0.25);
  // Two bytes a pixel (9 to 16 lights): a pixel differs when either of its bytes does.
  truth.shadow_mask = {1, 0, 1, 0x80, 1, 1, 0, 0};
  test.shadow_mask = {1, 0, 1, 0x00, 0, 1, 0, 0};
  truth.shadow_mask_bytes = test.shadow_mask_bytes = 2;
  const ShadowError e = compare_frames(truth, test).shadow.value();
  EXPECT_EQ(e.pixels, 4u);
  EXPECT_EQ(e.differing, 2u);
  test.shadow_mask_bytes = 1;
  EXPECT_THROW(compare_frames(truth, test), std::invalid_argument);
}

}  // namespace
}  // namespace rr
