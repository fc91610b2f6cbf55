// Framing (frame_bounds, view_camera): every corner of the framed box projects inside the image and
// between the near and far planes, for seeded random boxes, fields of view and aspect ratios; the
// apartment framed by view_camera shows every vertex of its tessellation; a camera that does not
// ask for a frame is returned unchanged.
#include "render/core/camera.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/scene_json.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>

#include <random>

namespace {

// Inside the view volume: clip-space x, y, z within [-w, w] and w > 0.
void expect_in_view(const rr::ViewTransform& view, rr::Vec3 p, const std::string& what) {
  const rr::Vec4 c = view.clip_from_world * rr::Vec4(p, 1.0);
  ASSERT_GT(c.w, 0.0) << what;
  EXPECT_LE(std::abs(c.x), c.w) << what;
  EXPECT_LE(std::abs(c.y), c.w) << what;
  EXPECT_LE(std::abs(c.z), c.w) << what;
}

TEST(FrameBounds, EveryCornerOfRandomBoxesIsInView) {
  const unsigned seed = 16016;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> coord(-50.0, 50.0), extent(0.0, 40.0), fov(10.0, 120.0);
  std::uniform_int_distribution<int> side(16, 2000);
  for (int trial = 0; trial < 500; ++trial) {
    const rr::Vec3 lo(coord(rng), coord(rng), coord(rng));
    const rr::Vec3 hi = lo + rr::Vec3(extent(rng), extent(rng), extent(rng));
    rr::Camera base;
    base.fov_y_deg = fov(rng);
    base.frame_all = true;
    const int width = side(rng), height = side(rng);
    const rr::Camera c = rr::frame_bounds(base, lo, hi, width, height);
    EXPECT_FALSE(c.frame_all);
    EXPECT_EQ(c.fov_y_deg, base.fov_y_deg);
    const rr::ViewTransform view = rr::make_view(c, width, height);
    for (int corner = 0; corner < 8; ++corner) {
      const rr::Vec3 p(corner & 1 ? hi.x : lo.x, corner & 2 ? hi.y : lo.y, corner & 4 ? hi.z : lo.z);
      expect_in_view(
          view, p,
          "seed " + std::to_string(seed) + " trial " + std::to_string(trial) + " corner " + std::to_string(corner));
    }
  }
}

TEST(FrameBounds, TheFrameLooksDownFromPlusZAtTheCentre) {
  const rr::Camera c = rr::frame_bounds(rr::Camera{}, rr::Vec3(0.0), rr::Vec3(10.0, 2.0, 8.0), 640, 480);
  EXPECT_EQ(c.target, rr::Vec3(5.0, 1.0, 4.0));
  const rr::Vec3 d = glm::normalize(c.target - c.position);
  EXPECT_NEAR(glm::length(d - rr::frame_direction()), 0.0, 1e-12);
  EXPECT_LT(d.y, 0.0);
  EXPECT_LT(d.z, 0.0);
}

TEST(FrameBounds, ViewCameraFramesEveryVertexOfTheApartment) {
  rr::RenderRequest request = rr::request_from_json(rr::testing::example_request("apartment", 640, 480));
  const rr::PreparedScene scene = rr::prepare_scene(request.scene);
  EXPECT_EQ(rr::view_camera(request.camera, request.options, scene.soup).position, request.camera.position)
      << "a camera that asks for no frame is kept";
  request.camera.frame_all = true;
  const rr::Camera framed = rr::view_camera(request.camera, request.options, scene.soup);
  const rr::ViewTransform view = rr::make_view(framed, 640, 480);
  for (const rr::Vec3& p : scene.soup.positions) expect_in_view(view, p, "apartment vertex");
}

}  // namespace
