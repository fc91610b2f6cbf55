// The roomrender subcommands behind cli/main.cpp: render (request -> PNG, ids, timings line),
// export (request -> Wavefront OBJ of the tessellated scene) and serve (the HTTP service). Each takes
// the arguments after its name and returns the exit code: 0 ok, 1 failed, 2 usage error. Machine
// output is one JSON line: results on stdout (stderr when a file argument of - takes stdout), errors
// on stderr as {"error": ..., "pointer": ...}.
#pragma once

#include "render/core/tessellate.hpp"
#include "render/scene_io/scene_json.hpp"
#include "server/serve_command.hpp"

#include <functional>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace rr::cli {

using server::UsageError;
using server::version;

std::string usage_text();  // every subcommand with its options, for `roomrender help`

// The limits requests are parsed with: the service's defaults, and "ref"s resolving to the meshes
// of the furniture catalogue (ROOMRENDER_CATALOGUE_DIR, else the source tree's catalogue/), which is
// read the first time a request places one. So a scene holding catalogue pieces renders here as it
// does on the service.
ParseLimits request_limits();

int run_render(std::span<const std::string> args);
// compare REFERENCE TEST: two id buffers (visibility error) or two PNGs (RMSE, PSNR) -> one JSON
// line of error measures (render/core/error_metrics.hpp); sizes must match.
int run_compare(std::span<const std::string> args);
int run_export(std::span<const std::string> args);
int run_import(std::span<const std::string> args);  // FILE -> request JSON on stdout
// bench-render: one scene rendered K timed frames from the command line's camera (OpenGL
// conventions, as bench/peer/osmesa_bench.cpp takes them); prints one JSON line of setup time,
// frame_ms_min/median/max and per-stage medians, parsing excluded; --list prints the pipelines and
// shadings this build has.
int run_bench_render(std::span<const std::string> args);

// The tessellated scene as Wavefront OBJ: `comment` as '#' lines, then per polygon in id order its
// vertices as `v` lines (shortest round-trip decimals, so reading back is exact) and one `f` line,
// so polygon id k is the k-th `f` line.
std::string encode_obj(const PolygonSoup& soup, std::string_view comment);

}  // namespace rr::cli
