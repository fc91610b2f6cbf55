// JSON Pointer building for InputError (RFC 6901): a reference token escapes '~' as "~0" and '/' as
// "~1". '~' is replaced first in spirit: each character is escaped on its own, so "~1" in a key
// becomes "~01" and reads back as the original two characters.
#include "render/scene_io/errors.hpp"

namespace rr {

std::string pointer_append(const std::string& pointer, const std::string& token) {
  std::string out;
  out.reserve(pointer.size() + token.size() + 1);
  out += pointer;
  out += '/';
  for (char c : token) {
    if (c == '~') {
      out += "~0";
    } else if (c == '/') {
      out += "~1";
    } else {
      out += c;
    }
  }
  return out;
}

std::string pointer_append(const std::string& pointer, size_t index) {
  return pointer + '/' + std::to_string(index);
}

}  // namespace rr
