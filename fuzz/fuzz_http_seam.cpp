// libFuzzer entry point: each input is the bytes of a request, parsed by the connection front and by
// cpp-httplib as the front hands it on (http_seam_harness.cpp). A disagreement aborts with what
// differs; so does a crash, sanitizer report, leak or hang.
#include "fuzz/http_seam_harness.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string difference = rr::fuzz::seam_disagreement(std::string_view(reinterpret_cast<const char*>(data), size));
  if (!difference.empty()) {
    std::fprintf(stderr, "the front and httplib disagree: %s\n", difference.c_str());
    std::abort();
  }
  return 0;
}
