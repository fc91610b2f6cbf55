// The sub-sample patterns (sample_pattern.hpp). The 4-, 8- and 16-sample tables are Direct3D's
// standard multisample positions (D3D11_STANDARD_MULTISAMPLE_PATTERN), given there in 1/16 pixel
// from the centre; here they are moved to the corner origin.
#include "render/core/sample_pattern.hpp"

#include <array>
#include <stdexcept>
#include <string>

namespace rr {
namespace {

template <size_t N>
constexpr std::array<glm::vec2, N> from_centre_sixteenths(const int (&xy)[N][2]) {
  std::array<glm::vec2, N> out{};
  for (size_t i = 0; i < N; ++i) out[i] = {0.5f + float(xy[i][0]) / 16.0f, 0.5f + float(xy[i][1]) / 16.0f};
  return out;
}

constexpr int d3d4[4][2] = {{-2, -6}, {6, -2}, {-6, 2}, {2, 6}};
constexpr int d3d8[8][2] = {{1, -3}, {-1, 3}, {5, 1}, {-3, -5}, {-5, 5}, {-7, -1}, {3, 7}, {7, -7}};
constexpr int d3d16[16][2] = {{1, 1},  {-1, -3}, {-3, 2},  {4, -1}, {-5, -2}, {2, 5},  {5, 3}, {3, -5},
                              {-2, 6}, {0, -7},  {-4, -6}, {-6, 4}, {-8, 0},  {7, -4}, {6, 7}, {-7, -8}};

constexpr std::array<glm::vec2, 1> centre = {glm::vec2{0.5f, 0.5f}};
constexpr auto pattern4 = from_centre_sixteenths(d3d4);
constexpr auto pattern8 = from_centre_sixteenths(d3d8);
constexpr auto pattern16 = from_centre_sixteenths(d3d16);

constexpr std::array<glm::vec2, 256> grid16() {
  std::array<glm::vec2, 256> out{};
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) out[size_t(y * 16 + x)] = {(float(x) + 0.5f) / 16.0f, (float(y) + 0.5f) / 16.0f};
  }
  return out;
}
constexpr auto pattern256 = grid16();

}  // namespace

bool is_sample_count(int samples) { return samples == 1 || samples == 4 || samples == 8 || samples == 16; }

std::span<const glm::vec2> sample_pattern(int samples) {
  switch (samples) {
    case 1:
      return centre;
    case 4:
      return pattern4;
    case 8:
      return pattern8;
    case 16:
      return pattern16;
    case 256:
      return pattern256;
    default:
      throw std::invalid_argument("no sample pattern of " + std::to_string(samples) + " samples");
  }
}

}  // namespace rr
