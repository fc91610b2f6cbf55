// Where a pixel's coverage sub-samples sit (docs/antialiasing.md): offsets from the pixel's top-left
// corner, in pixels, each in [0, 1)^2. Every anti-aliased pipeline and the reference's supersampled
// rays read the same pattern, so their sub-samples see the same points of the scene.
#pragma once

#include <glm/vec2.hpp>

#include <span>

namespace rr {

// The sub-sample counts options.antialias takes (1, 4, 8, 16).
bool is_sample_count(int samples);

// The pattern of `samples` sub-samples: 1 is the pixel centre (0.5, 0.5); 4, 8 and 16 are the
// standard Direct3D multisample patterns (each sample alone on its row and column of the
// 1/16-pixel lattice for 4 and 8); 256 is the regular 16 x 16 grid of cell centres, the reference's
// ground truth for edge error. Any other count throws std::invalid_argument.
std::span<const glm::vec2> sample_pattern(int samples);

}  // namespace rr
