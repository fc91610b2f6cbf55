// Sight cones (render/core/sight_cones.hpp) on hand-placed viewpoints whose answers follow from
// the geometry: cones facing each other meet, cones turned apart do not, and nearly parallel
// narrow cones meet only in a box long enough to hold where they cross.
#include "render/core/sight_cones.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace rr {
namespace {

Mat4 view_toward(Vec3 eye, Vec3 forward) {
  return glm::perspective(0.5 * std::numbers::pi, 1.0, 1e-4, 1e6) * glm::lookAt(eye, eye + forward, Vec3(0, 0, 1));
}

bool meet(Vec3 a, Vec3 a_forward, ViewRegion ra, Vec3 b, Vec3 b_forward, ViewRegion rb, Vec3 lo, Vec3 hi) {
  std::vector<HalfSpace> cones;
  add_sight_cone(view_toward(a, a_forward), ra, cones);
  add_sight_cone(view_toward(b, b_forward), rb, cones);
  EXPECT_EQ(cones.size(), 10u);
  return half_spaces_meet_in_box(cones, lo, hi, 1e-9);
}

TEST(SightCones, FacingConesMeetAndConesTurnedApartDoNot) {
  const Vec3 lo(-20.0), hi(30.0), a(0.0), b(10.0, 0.0, 0.0), x(1.0, 0.0, 0.0);
  EXPECT_TRUE(meet(a, x, {}, b, -x, {}, lo, hi));
  EXPECT_FALSE(meet(a, -x, {}, b, x, {}, lo, hi));
  // One turned away, the other toward it: the second sees the first's whole cone.
  EXPECT_TRUE(meet(a, -x, {}, b, -x, {}, lo, hi));
  // Sideways cones of 90 degrees from points 10 m apart along y meet 5 m out.
  const Vec3 c(0.0, 10.0, 0.0);
  EXPECT_TRUE(meet(a, x, {}, c, x, {}, lo, hi));
  EXPECT_FALSE(meet(a, x, {}, c, x, {}, lo, Vec3(4.9, 30.0, 30.0)));
  EXPECT_TRUE(meet(a, x, {}, c, x, {}, lo, Vec3(5.1, 30.0, 30.0)));
}

TEST(SightCones, NarrowConesMeetOnlyWhereTheyCross) {
  // The view's x runs along world -y here (lookAt toward +x with z up), so region x in [0.05, 0.15]
  // of the eye at y 0 turns its cone toward -y by 0.05..0.15 of its depth, and region x in
  // [-0.15, -0.05] of the eye at y -10 turns it toward +y: they cross between depths 10 / 0.3 and
  // 10 / 0.1 metres along x.
  const Vec3 x(1.0, 0.0, 0.0), a(0.0), b(0.0, -10.0, 0.0);
  const ViewRegion ra{0.05, -0.1, 0.15, 0.1}, rb{-0.15, -0.1, -0.05, 0.1};
  const Vec3 lo(-1.0, -11.0, -50.0);
  EXPECT_TRUE(meet(a, x, ra, b, x, rb, lo, Vec3(200.0, 1.0, 50.0)));
  EXPECT_FALSE(meet(a, x, ra, b, x, rb, lo, Vec3(30.0, 1.0, 50.0)));
  EXPECT_TRUE(meet(a, x, ra, b, x, rb, lo, Vec3(36.0, 1.0, 50.0)));
}

}  // namespace
}  // namespace rr
