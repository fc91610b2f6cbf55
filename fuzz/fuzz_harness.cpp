// The fuzz path (fuzz_harness.hpp): parse, then prepare_scene and render() as every caller does,
// with the request shrunk to a tiny render and its variant picked from the input's hash. No state survives between
// calls.
#include "fuzz/fuzz_harness.hpp"

#include "render/core/hash.hpp"
#include "render/core/png.hpp"
#include "render/core/scene_id.hpp"
#include "render/core/scene_names.hpp"
#include "render/core/tessellate.hpp"
#include "render/pipelines/pipeline.hpp"
#include "render/pipelines/render.hpp"
#include "render/scene_io/errors.hpp"

#include <algorithm>
#include <cmath>

namespace rr::fuzz {

ParseLimits fuzz_limits() {
  ParseLimits limits;
  limits.max_polygons = 4000;  // BSP/Newell splitting is superlinear: keep each run short
  limits.max_cylinder_segments = 256;
  limits.max_floor_cells = 4096;
  return limits;
}

Variant variant_of(std::string_view bytes) {
  uint64_t h = fnv1a(bytes);
  Variant v;
  v.pipeline = pipeline_id(pipeline_table()[h % pipeline_table().size()]);
  h /= pipeline_table().size();
  v.shading = shading_names[h % shading_names.size()].value;
  h /= shading_names.size();
  v.painter_key = painter_key_names[h % painter_key_names.size()].value;
  h /= painter_key_names.size();
  v.shadows = (h % 2) == 1;
  h /= 2;
  v.png = png_compression_names[h % png_compression_names.size()].value;
  return v;
}

void shrink_for_fuzzing(RenderRequest& request, const Variant& variant) {
  RenderOptions& o = request.options;
  // Keep the aspect ratio (the projection depends on it) while capping the longer side.
  int longer = std::max(o.width, o.height);
  if (longer > max_fuzz_side) {
    double scale = double(max_fuzz_side) / double(longer);
    o.width = std::max(1, int(std::lround(o.width * scale)));
    o.height = std::max(1, int(std::lround(o.height * scale)));
  }
  o.pipeline = variant.pipeline;
  o.shading = variant.shading;
  o.painter_key = variant.painter_key;
  o.shadows = variant.shadows;
  o.shadow.size = 64;  // the schema's minimum
  o.png_compression = variant.png;
}

Outcome run_request_bytes(std::string_view bytes, const Variant& variant) {
  Outcome out;
  RenderRequest request;
  try {
    request = parse_request(bytes, fuzz_limits());
  } catch (const InputError& e) {
    out.error_pointer = e.pointer();
    return out;
  }
  shrink_for_fuzzing(request, variant);
  const PreparedScene scene = prepare_scene(std::move(request.scene));
  out.png = render(request, scene).png;  // one thread, no caches: nothing survives the call
  out.rendered = true;
  return out;
}

}  // namespace rr::fuzz
