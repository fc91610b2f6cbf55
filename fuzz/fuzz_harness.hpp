// One fuzz input -> parse/validate -> tessellate -> a tiny render -> PNG, shared by the libFuzzer
// target (fuzz_render_request.cpp) and the regression test (tests/unit/test_fuzz_regressions.cpp),
// so a saved crash replays through exactly the code that found it. The request's image is shrunk
// to at most 32x32 and its work capped so one input takes milliseconds.
#pragma once

#include "render/core/scene.hpp"
#include "render/scene_io/scene_json.hpp"

#include <cstdint>
#include <string>
#include <string_view>

namespace rr::fuzz {

constexpr int max_fuzz_side = 32;

// Tighter than the service's limits so that every accepted input renders in milliseconds under
// ASan; an input beyond them is a clean InputError(too_large), as in the service.
ParseLimits fuzz_limits();

// The render variant (pipeline, shading, painter key, shadows, PNG mode) an input is drawn with:
// chosen from an FNV-1a hash of the bytes, so every input maps to one variant deterministically
// and mutations spread over all of them.
struct Variant {
  PipelineId pipeline;
  ShadingMode shading = ShadingMode::flat;
  PainterKey painter_key = PainterKey::mean;
  bool shadows = false;
  PngCompression png = PngCompression::fast;
};
Variant variant_of(std::string_view bytes);

// Applies the variant and the size caps (image <= 32x32 keeping its aspect, shadow map 64).
void shrink_for_fuzzing(RenderRequest& request, const Variant& variant);

struct Outcome {
  bool rendered = false;      // false: the input was refused with an InputError
  std::string error_pointer;  // the InputError's JSON Pointer when refused
  std::string png;            // the encoded image when rendered
};

// Runs the whole path with the given variant. Throws nothing but what the renderer would let escape
// (a bug: libFuzzer reports it as a crash, the regression test as a failure).
Outcome run_request_bytes(std::string_view bytes, const Variant& variant);

// What the fuzz target runs: the variant chosen by the input's hash.
inline Outcome run_request_bytes(std::string_view bytes) { return run_request_bytes(bytes, variant_of(bytes)); }

}  // namespace rr::fuzz
