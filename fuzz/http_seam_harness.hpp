// The differential check of the HTTP seam (server/httplib_bridge.hpp): one input's bytes go to the
// connection front's parser and, as the front would hand them on, to cpp-httplib's request
// processing; the two must agree on method, target, path, query, headers, body length and whether
// the connection stays open. Shared by the libFuzzer target (fuzz_http_seam.cpp) and the unit test
// (tests/unit/test_http_seam.cpp), so a saved finding replays through exactly the code that found it.
#pragma once

#include <string>
#include <string_view>

namespace rr::fuzz {

// "" when the two parsers agree on `bytes` (or the front refuses them, or needs more: then httplib
// never sees them), else what differs, in words. `bytes` starts at a request line; the front's
// default limits apply. A head that announces a body is taken as screening would pass it: the
// Expect line is cut and the body read (as much of it as `bytes` holds).
std::string seam_disagreement(std::string_view bytes);

}  // namespace rr::fuzz
