// libFuzzer entry point: each input is an encoded image handed to decode_texture (texture.hpp) with
// the service's limits. It must decode or be refused with a reason; a decoded image must have its
// whole mip chain. A crash, sanitizer report, leak or hang is a finding.
#include "render/core/texture.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  rr::TextureError error;
  const auto image = rr::decode_texture({data, size}, {}, &error);
  if (image ? image->levels.empty() || image->levels.back().width * image->levels.back().height != 1
            : error.message.empty()) {
    std::abort();
  }
  return 0;
}
