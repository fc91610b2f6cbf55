// A zip archive held in memory (a .sh3d home, a zip of an OBJ and its .mtl) -> its entry names and the
// bytes of the entries asked for, read with libzip under ArchiveLimits: the archive is refused, never
// partly read, when it has too many entries, an unsafe name or a declared size past a limit, and an
// entry inflating past its budget is cut off while it inflates, so memory stays bounded whatever the
// headers claim. Errors are InputError at "/entry/<name>" (the name as one JSON Pointer token).
#pragma once

#include "render/scene_io/errors.hpp"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rr {

struct ArchiveLimits {
  size_t max_entries = 10'000;              // .sh3d homes hold one entry per model and texture
  uint64_t max_entry_bytes = 64ull << 20;   // inflated, per entry: the import body limit
  uint64_t max_total_bytes = 256ull << 20;  // inflated, declared over all entries and read in all
  // Inflated / compressed, per entry. Text models deflate 3-10x; only entries inflating past
  // ratio_floor_bytes are held to it, so a small run of zeros is no bomb.
  double max_ratio = 100.0;
  uint64_t ratio_floor_bytes = 1ull << 20;
};

// What Archive throws: an InputError about the archive itself (never about an entry's content), so
// an importer that turns its own errors into errors inside an entry can tell the two apart.
class ArchiveError : public InputError {
 public:
  using InputError::InputError;
};

// True when a zip's local file header starts `bytes`.
bool looks_like_zip(std::string_view bytes);

// The pointer of an archive entry: "/entry/" + the name escaped as one JSON Pointer token.
std::string entry_pointer(const std::string& name);

// `error` told as an error inside entry `name`: pointers prefixed with entry_pointer(name) and
// details with "entry 'name': ".
InputError error_in_entry(const InputError& error, const std::string& name);

class Archive {
 public:
  // Reads the central directory of `zip_bytes`, which must outlive the Archive. Throws ArchiveError:
  // malformed (not a zip, truncated: naming the last entry whose header survives), invalid (an
  // absolute name, a ".." step, a backslash or NUL), too_large (entry count, declared sizes).
  Archive(std::string_view zip_bytes, const ArchiveLimits& limits = {});
  Archive(std::string&& temporary, const ArchiveLimits& limits = {}) = delete;  // would dangle
  ~Archive();
  Archive(const Archive&) = delete;
  Archive& operator=(const Archive&) = delete;

  // Entry names in the archive's order, directories ("a/") left out.
  const std::vector<std::string>& names() const { return names_; }
  bool contains(const std::string& name) const;
  // `name` as an entry: the entry of that exact name, else the entry with that base name (the part
  // after the last '/') nearest the top, the first in archive order among equals; nullopt if none.
  std::optional<std::string> resolve(const std::string& name) const;
  // The inflated bytes of entry `name` (which must be one of names()). Throws InputError at the
  // entry: malformed when its data is corrupt or truncated, too_large past a limit (checked before
  // inflating on the declared size, and again on the bytes actually inflated).
  std::string read(const std::string& name);

 private:
  struct Handle;
  std::unique_ptr<Handle> zip_;
  ArchiveLimits limits_;
  std::vector<std::string> names_;
  std::vector<uint64_t> indices_;  // libzip's index of each name
  uint64_t bytes_read_ = 0;
};

}  // namespace rr
