// A zip -> the importer of its main file, with the archive's other entries as its companion files:
// a Sweet Home 3D home (Home.xml of a .sh3d, else the one *.xml at the top level) with its furniture
// models, or an OBJ with its .mtl. Errors in the main file are told inside its entry
// ("/entry/Home.xml/home/wall/3", "/entry/model.obj/line/7"); the archive's own errors as they are.
#include "render/import/import.hpp"

#include <algorithm>
#include <cctype>

namespace rr {

namespace {

using Kind = InputError::Kind;

bool has_extension(const std::string& name, std::string_view ext) {
  if (name.size() < ext.size()) return false;
  std::string tail = name.substr(name.size() - ext.size());
  std::transform(tail.begin(), tail.end(), tail.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return tail == ext;
}

std::string directory_of(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? "" : path.substr(0, slash + 1);
}

// The one entry that `pick` accepts; `what` names it in the errors when there is none or several.
std::string only_entry(const std::vector<std::string>& candidates, const std::string& what) {
  if (candidates.empty()) throw InputError(Kind::invalid, "/entry", "the archive holds no " + what);
  if (candidates.size() > 1) {
    throw InputError(Kind::invalid, entry_pointer(candidates[1]),
                     "the archive holds more than one " + what + " ('" + quote_input(candidates[0]) + "' and '" +
                         quote_input(candidates[1]) + "'): send one per archive");
  }
  return candidates[0];
}

std::string home_entry(const Archive& archive) {
  if (archive.contains("Home.xml")) return "Home.xml";
  std::vector<std::string> xml;
  for (const std::string& n : archive.names()) {
    if (n.find('/') == std::string::npos && has_extension(n, ".xml")) xml.push_back(n);
  }
  if (xml.empty() && archive.contains("Home")) {
    throw InputError(Kind::invalid, entry_pointer("Home"),
                     "the archive holds only the Java-serialised 'Home' of Sweet Home 3D before 5.3, no Home.xml: "
                     "re-save the home with a newer Sweet Home 3D");
  }
  return only_entry(xml, "home (Home.xml, or one *.xml at the top level)");
}

std::string obj_entry(const Archive& archive) {
  std::vector<std::string> obj;
  for (const std::string& n : archive.names()) {
    if (has_extension(n, ".obj")) obj.push_back(n);
  }
  return only_entry(obj, "OBJ model (*.obj)");
}

// Runs the importer of `main`, telling its own errors inside that entry; the archive's errors
// (reading a companion entry) pass through as they are.
template <class Import>
ImportResult import_entry(const std::string& main, Import&& import) {
  try {
    return import();
  } catch (const ArchiveError&) {
    throw;
  } catch (const InputError& e) {
    throw error_in_entry(e, main);
  }
}

}  // namespace

ImportResult import_archive(std::string_view zip_bytes, ImportFormat format, const ImportOptions& options) {
  Archive archive(zip_bytes, options.archive);
  const std::string main = format == ImportFormat::obj ? obj_entry(archive) : home_entry(archive);
  const std::string text = archive.read(main);
  ImportOptions with_entries = options;
  // Names in the main file are relative to its folder, as for files on disk; an entry not there is
  // looked up by its base name (Sweet Home 3D writes a model's catalogue path, the archive a number).
  with_entries.read_companion = [&archive,
                                 dir = directory_of(main)](const std::string& name) -> std::optional<std::string> {
    std::optional<std::string> entry = archive.resolve(dir + name);
    if (!entry) return std::nullopt;
    return archive.read(*entry);
  };
  switch (format) {
    case ImportFormat::obj:
      return import_entry(main, [&] { return import_obj(text, with_entries); });
    case ImportFormat::sweethome3d:
      return import_entry(main, [&] { return import_sweethome3d(text, with_entries); });
    case ImportFormat::r2v:
      break;
  }
  throw InputError(Kind::invalid, "", "R2V plans are plain text, not archives");
}

}  // namespace rr
