// Reading a whole input file in the benchmark programs: the bytes, or std::runtime_error naming the
// path when it cannot be read (a missing scene is a clear error, not an empty request).
#pragma once

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace rr::bench {

inline std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace rr::bench
