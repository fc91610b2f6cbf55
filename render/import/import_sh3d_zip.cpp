// .sh3d (a zip archive) -> the text of its Home.xml entry, through libzip reading from memory.
// Sweet Home 3D writes Home.xml beside the Java-serialised "Home" entry since version 5.3; older
// files hold only the latter, which we cannot read.
#include "render/import/import.hpp"

#include <zip.h>

#include <memory>

namespace rr {

namespace {

// Home.xml of the nine example homes is below 120 kB; 64 MB leaves room for any real home while a
// zip bomb is refused before it is inflated.
constexpr zip_uint64_t max_home_xml_bytes = 64ull << 20;

[[noreturn]] void fail(const std::string& detail) {
  throw InputError(InputError::Kind::malformed, "", ".sh3d archive: " + detail);
}

}  // namespace

std::string extract_sh3d_home_xml(std::string_view zip_bytes) {
  zip_error_t error;
  zip_error_init(&error);
  zip_source_t* source = zip_source_buffer_create(zip_bytes.data(), zip_bytes.size(), 0, &error);
  if (!source) fail(zip_error_strerror(&error));
  zip_t* archive = zip_open_from_source(source, ZIP_RDONLY, &error);
  if (!archive) {
    zip_source_free(source);
    std::string message = zip_error_strerror(&error);
    zip_error_fini(&error);
    fail("not a readable zip (" + message + ")");
  }
  zip_error_fini(&error);
  std::unique_ptr<zip_t, decltype(&zip_discard)> owner(archive, zip_discard);  // also frees the source
  zip_int64_t index = zip_name_locate(archive, "Home.xml", 0);
  if (index < 0) fail("no Home.xml entry (homes saved before Sweet Home 3D 5.3 have none: re-save the home)");
  zip_stat_t stat;
  zip_stat_init(&stat);
  if (zip_stat_index(archive, zip_uint64_t(index), 0, &stat) != 0 || !(stat.valid & ZIP_STAT_SIZE)) {
    fail("cannot read the size of Home.xml");
  }
  if (stat.size > max_home_xml_bytes) {
    throw InputError(InputError::Kind::too_large, "", ".sh3d archive: Home.xml is larger than 64 MB");
  }
  std::unique_ptr<zip_file_t, decltype(&zip_fclose)> file(zip_fopen_index(archive, zip_uint64_t(index), 0), zip_fclose);
  if (!file) fail("cannot open Home.xml");
  std::string text(size_t(stat.size), '\0');
  zip_int64_t read = zip_fread(file.get(), text.data(), stat.size);
  if (read < 0 || zip_uint64_t(read) != stat.size) fail("Home.xml is truncated or corrupt");
  return text;
}

}  // namespace rr
