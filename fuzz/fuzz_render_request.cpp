// libFuzzer entry point: each input is request JSON text, run through parse/validation ->
// tessellation -> a <= 32x32 render with a hash-chosen pipeline and shading -> PNG encoding
// (fuzz_harness.cpp). A refused input is fine; a crash, sanitizer report, leak or hang is a finding.
#include "fuzz/fuzz_harness.hpp"

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  rr::fuzz::run_request_bytes(std::string_view(reinterpret_cast<const char*>(data), size));
  return 0;
}
