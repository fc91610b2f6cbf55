// Zip archives for the importer tests, built in memory with libzip: entries stored or deflated, and
// the byte surgery a hostile archive needs (central-directory sizes that lie).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rr::testing {

struct ZipEntry {
  std::string name;
  std::string bytes;
  bool deflate = true;  // false: stored as is
};

// The bytes of a zip holding `entries` in order. Throws std::runtime_error when libzip refuses.
std::string make_zip(const std::vector<ZipEntry>& entries);

// `zip` with the uncompressed size of every central-directory entry named `name` set to `size`
// (the local header keeps the true one, as a tool meaning harm might leave it).
std::string with_declared_size(std::string zip, const std::string& name, uint32_t size);

}  // namespace rr::testing
