// make_zip through libzip writing into a memory source (zip_source_buffer_create + keep after close),
// and central-directory patching by the fixed offsets of the zip format (APPNOTE 4.3.12).
#include "support/zip_builder.hpp"

#include <zip.h>

#include <stdexcept>

namespace rr::testing {

namespace {

void check(bool ok, const char* what) {
  if (!ok) throw std::runtime_error(std::string("make_zip: ") + what);
}

std::string source_bytes(zip_source_t* source) {
  check(zip_source_open(source) == 0, "cannot reopen the archive");
  std::string out;
  char chunk[65536];
  for (zip_int64_t n; (n = zip_source_read(source, chunk, sizeof chunk)) > 0;) out.append(chunk, size_t(n));
  zip_source_close(source);
  return out;
}

}  // namespace

std::string make_zip(const std::vector<ZipEntry>& entries) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* target = zip_source_buffer_create(nullptr, 0, 0, &error);
  check(target != nullptr, "cannot make a memory source");
  zip_source_keep(target);  // zip_close frees what it was given; the bytes are read afterwards
  zip_t* archive = zip_open_from_source(target, ZIP_TRUNCATE, &error);
  check(archive != nullptr, "cannot open the memory source");
  for (const ZipEntry& e : entries) {
    zip_source_t* data = zip_source_buffer(archive, e.bytes.data(), e.bytes.size(), 0);
    check(data != nullptr, "cannot add an entry");
    zip_int64_t index = zip_file_add(archive, e.name.c_str(), data, ZIP_FL_ENC_UTF_8);
    check(index >= 0, "cannot add an entry");
    zip_set_file_compression(archive, zip_uint64_t(index), e.deflate ? ZIP_CM_DEFLATE : ZIP_CM_STORE, 0);
  }
  check(zip_close(archive) == 0, "cannot write the archive");
  std::string bytes = source_bytes(target);
  zip_source_free(target);
  zip_error_fini(&error);
  return bytes;
}

std::string with_declared_size(std::string zip, const std::string& name, uint32_t size) {
  for (size_t at = zip.find("PK\x01\x02"); at != std::string::npos; at = zip.find("PK\x01\x02", at + 4)) {
    if (at + 46 > zip.size()) break;
    const size_t length = uint8_t(zip[at + 28]) | (uint8_t(zip[at + 29]) << 8);
    if (zip.compare(at + 46, length, name) != 0) continue;
    for (int k = 0; k < 4; ++k) zip[at + 24 + size_t(k)] = char((size >> (8 * k)) & 0xff);
  }
  return zip;
}

}  // namespace rr::testing
