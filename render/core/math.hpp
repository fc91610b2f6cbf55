// The one place GLM is included and configured. World and view space use doubles (scenes may sit
// 1e7 m from the origin); colours and shading normals use floats.
#pragma once

#define GLM_FORCE_SILENT_WARNINGS
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>

namespace rr {

using Vec2 = glm::dvec2;
using Vec3 = glm::dvec3;
using Vec4 = glm::dvec4;
using Mat3 = glm::dmat3;
using Mat4 = glm::dmat4;
using Color = glm::vec3;  // display values in [0, 1], no gamma

constexpr double pi = 3.14159265358979323846;

inline double radians(double degrees) { return degrees * (pi / 180.0); }

inline bool is_finite(Vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace rr
