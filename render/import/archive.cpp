// Bounded zip reading (archive.hpp) through libzip from memory. Sizes in the headers are checked
// first, so an honest bomb is refused before anything inflates; then each entry is inflated in
// 64 KiB steps into a buffer that may not grow past its budget, so a lying header costs at most the
// budget. libzip checks each entry's CRC when its data ends, which catches corrupt streams.
#include "render/import/archive.hpp"

#include <zip.h>

#include <algorithm>
#include <cstring>
#include <set>

namespace rr {

struct Archive::Handle {
  zip_t* zip = nullptr;
  ~Handle() {
    if (zip) zip_discard(zip);  // also frees the source, which never owned the bytes
  }
};

namespace {

using Kind = InputError::Kind;

std::string mib(uint64_t bytes) {
  if (bytes % (1ull << 20) == 0) return std::to_string(bytes >> 20) + " MiB";
  return std::to_string(bytes) + " bytes";
}

[[noreturn]] void fail_at(Kind kind, const std::string& name, const std::string& detail) {
  throw ArchiveError(kind, entry_pointer(name), "archive entry '" + quote_input(name) + "': " + detail);
}

uint16_t little_u16(std::string_view bytes, size_t at) {
  return uint16_t(uint8_t(bytes[at]) | (uint8_t(bytes[at + 1]) << 8));
}

// The name in the last local file header found in `bytes`: where a truncated archive was cut.
std::optional<std::string> last_local_entry(std::string_view bytes) {
  std::optional<std::string> last;
  for (size_t at = bytes.find("PK\x03\x04"); at != std::string_view::npos; at = bytes.find("PK\x03\x04", at + 4)) {
    if (at + 30 > bytes.size()) break;
    const size_t length = little_u16(bytes, at + 26);
    if (length == 0 || at + 30 + length > bytes.size()) continue;
    last = std::string(bytes.substr(at + 30, length));
  }
  return last;
}

[[noreturn]] void fail_open(std::string_view bytes, int code, const std::string& message) {
  if (!looks_like_zip(bytes)) throw ArchiveError(Kind::malformed, "", "the file is not a zip archive");
  std::optional<std::string> last = last_local_entry(bytes);
  std::string detail = code == ZIP_ER_NOZIP ? "its central directory is missing: the archive is truncated"
                                            : "it cannot be read (" + message + ")";
  if (!last) throw ArchiveError(Kind::malformed, "", "the zip archive is unreadable: " + detail);
  fail_at(Kind::malformed, *last, detail + "; this is the last entry whose header survives");
}

// Names are only ever looked up, never written to disk, but an unsafe name is refused anyway: it
// could only come from a tool meaning harm, and a reader that later extracts must not trust it.
void check_name(const std::string& name) {
  if (name.empty()) throw ArchiveError(Kind::invalid, "/entry", "an archive entry has an empty name");
  if (name.front() == '/' || (name.size() > 1 && name[1] == ':' && std::isalpha(static_cast<unsigned char>(name[0])))) {
    fail_at(Kind::invalid, name, "absolute names are refused");
  }
  if (name.find('\\') != std::string::npos) fail_at(Kind::invalid, name, "names with a backslash are refused");
  size_t start = 0;
  while (start <= name.size()) {
    size_t end = std::min(name.find('/', start), name.size());
    if (name.compare(start, end - start, "..") == 0 && end - start == 2) {
      fail_at(Kind::invalid, name, "names with a '..' step are refused (path traversal)");
    }
    start = end + 1;
  }
}

std::string zip_error_text(zip_file_t* file) {
  const char* text = zip_file_strerror(file);
  return text ? text : "unknown error";
}

}  // namespace

bool looks_like_zip(std::string_view bytes) {
  return bytes.starts_with("PK\x03\x04") || bytes.starts_with("PK\x05\x06");
}

std::string entry_pointer(const std::string& name) { return pointer_append("/entry", name); }

InputError error_in_entry(const InputError& error, const std::string& name) {
  std::vector<FieldProblem> moved = error.errors();
  for (FieldProblem& e : moved) {
    e.pointer = entry_pointer(name) + e.pointer;
    e.detail = "entry '" + quote_input(name) + "': " + e.detail;
  }
  return InputError(error.kind(), std::move(moved), error.truncated());
}

Archive::Archive(std::string_view zip_bytes, const ArchiveLimits& limits) : zip_(new Handle), limits_(limits) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* source = zip_source_buffer_create(zip_bytes.data(), zip_bytes.size(), 0, &error);
  if (source) zip_->zip = zip_open_from_source(source, ZIP_RDONLY, &error);
  const int code = zip_error_code_zip(&error);
  const std::string message = zip_error_strerror(&error);
  zip_error_fini(&error);
  if (!zip_->zip) {
    if (source) zip_source_free(source);
    fail_open(zip_bytes, code, message);
  }
  const zip_int64_t count = zip_get_num_entries(zip_->zip, 0);
  std::set<std::string> seen;
  uint64_t declared_total = 0;
  for (zip_int64_t i = 0; i < count; ++i) {
    const char* raw = zip_get_name(zip_->zip, zip_uint64_t(i), ZIP_FL_ENC_GUESS);
    if (!raw)
      throw ArchiveError(Kind::malformed, "/entry", "archive entry " + std::to_string(i) + " has no readable name");
    const std::string name = raw;
    if (zip_uint64_t(i) >= limits_.max_entries) {
      fail_at(Kind::too_large, name,
              "the archive holds " + std::to_string(count) + " entries; at most " +
                  std::to_string(limits_.max_entries) + " are read");
    }
    check_name(name);
    if (!seen.insert(name).second) fail_at(Kind::invalid, name, "the name appears twice in the archive");
    zip_stat_t stat;
    zip_stat_init(&stat);
    if (zip_stat_index(zip_->zip, zip_uint64_t(i), 0, &stat) != 0 || !(stat.valid & ZIP_STAT_SIZE)) {
      fail_at(Kind::malformed, name, "its size cannot be read");
    }
    declared_total += stat.size;
    if (declared_total > limits_.max_total_bytes) {
      fail_at(Kind::too_large, name,
              "the entries up to this one inflate to " + std::to_string(declared_total) + " bytes; at most " +
                  mib(limits_.max_total_bytes) + " in all");
    }
    if (name.back() == '/') continue;  // a directory
    names_.push_back(name);
    indices_.push_back(zip_uint64_t(i));
  }
}

Archive::~Archive() = default;

bool Archive::contains(const std::string& name) const {
  return std::find(names_.begin(), names_.end(), name) != names_.end();
}

std::optional<std::string> Archive::resolve(const std::string& name) const {
  if (contains(name)) return name;
  const std::string base = name.substr(name.rfind('/') + 1);
  if (base.empty()) return std::nullopt;
  const std::string* best = nullptr;
  auto depth = [](const std::string& n) { return std::count(n.begin(), n.end(), '/'); };
  for (const std::string& n : names_) {
    if (n.size() < base.size() || n.compare(n.size() - base.size(), base.size(), base) != 0) continue;
    if (n.size() > base.size() && n[n.size() - base.size() - 1] != '/') continue;
    if (!best || depth(n) < depth(*best)) best = &n;
  }
  return best ? std::optional<std::string>(*best) : std::nullopt;
}

std::string Archive::read(const std::string& name) {
  auto it = std::find(names_.begin(), names_.end(), name);
  if (it == names_.end()) fail_at(Kind::invalid, name, "no such entry");
  const zip_uint64_t index = indices_[size_t(it - names_.begin())];
  zip_stat_t stat;
  zip_stat_init(&stat);
  if (zip_stat_index(zip_->zip, index, 0, &stat) != 0) fail_at(Kind::malformed, name, "its header cannot be read");
  const uint64_t compressed = (stat.valid & ZIP_STAT_COMP_SIZE) ? stat.comp_size : 0;
  const uint64_t by_ratio =
      std::max<uint64_t>(limits_.ratio_floor_bytes, uint64_t(limits_.max_ratio * double(compressed)));
  const uint64_t by_total = limits_.max_total_bytes - std::min(bytes_read_, limits_.max_total_bytes);
  const uint64_t budget = std::min({limits_.max_entry_bytes, by_total, by_ratio});
  auto refuse = [&](uint64_t size) {
    if (size > limits_.max_entry_bytes)
      fail_at(Kind::too_large, name, "inflates past " + mib(limits_.max_entry_bytes) + " (the limit per entry)");
    if (size > by_total)
      fail_at(Kind::too_large, name, "the entries read inflate past " + mib(limits_.max_total_bytes) + " in all");
    fail_at(Kind::too_large, name,
            "inflates past " + std::to_string(int(limits_.max_ratio)) + " times its " + std::to_string(compressed) +
                " compressed bytes (a zip bomb)");
  };
  if (stat.size > budget) refuse(stat.size);
  std::unique_ptr<zip_file_t, decltype(&zip_fclose)> file(zip_fopen_index(zip_->zip, index, 0), zip_fclose);
  if (!file) {
    zip_error_t* error = zip_get_error(zip_->zip);
    fail_at(Kind::malformed, name, std::string("it cannot be opened (") + zip_error_strerror(error) + ")");
  }
  std::string out;
  out.reserve(size_t(stat.size));
  char chunk[64 * 1024];
  while (true) {
    const zip_int64_t n = zip_fread(file.get(), chunk, sizeof chunk);
    if (n < 0)
      fail_at(Kind::malformed, name,
              "its compressed data is corrupt or truncated (" + zip_error_text(file.get()) + ")");
    if (n == 0) break;
    if (out.size() + uint64_t(n) > budget) refuse(out.size() + uint64_t(n));
    out.append(chunk, size_t(n));
  }
  if (out.size() != stat.size) {
    fail_at(Kind::malformed, name,
            "inflates to " + std::to_string(out.size()) + " bytes where its header says " + std::to_string(stat.size));
  }
  bytes_read_ += out.size();
  return out;
}

}  // namespace rr
