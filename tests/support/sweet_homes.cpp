// Sweet Home 3D homes zipped with their models and moved apart (sweet_homes.hpp).
#include "support/sweet_homes.hpp"

#include "support/test_support.hpp"
#include "support/zip_builder.hpp"

#include <algorithm>
#include <charconv>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <stdexcept>

namespace rr::testing {

namespace fs = std::filesystem;

namespace {

std::string base_name(const std::string& path) { return path.substr(path.rfind('/') + 1); }

std::string shifted(const std::string& number, double by) {
  double value = 0.0;
  auto [end, ec] = std::from_chars(number.data(), number.data() + number.size(), value);
  if (ec != std::errc() || end != number.data() + number.size()) throw std::runtime_error("not a number: " + number);
  char out[32];
  auto printed = std::to_chars(out, out + sizeof out, value + by);
  return std::string(out, printed.ptr);
}

}  // namespace

std::vector<fs::path> sweet_home_files() {
  std::vector<fs::path> out;
  auto dir = shared_data_dir();
  if (!dir) return out;
  for (const auto& e : fs::directory_iterator(*dir / "floorplans/sweethome3d")) {
    if (e.path().extension() == ".xml") out.push_back(e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> sweet_home_model_names(const std::string& xml) {
  std::vector<std::string> names;
  std::regex attribute(R"re(\bmodel=['"]([^'"]+)['"])re");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), attribute); it != std::sregex_iterator(); ++it) {
    if (std::find(names.begin(), names.end(), (*it)[1].str()) == names.end()) names.push_back((*it)[1].str());
  }
  return names;
}

std::vector<std::string> obj_material_libraries(const std::string& obj) {
  std::vector<std::string> out;
  std::regex line(R"(^mtllib\s+(\S+))");
  for (auto it = std::sregex_iterator(obj.begin(), obj.end(), line, std::regex_constants::match_default);
       it != std::sregex_iterator(); ++it) {
    out.push_back((*it)[1].str());
  }
  return out;
}

std::string sweet_home_zip(const fs::path& home, const std::string& xml_text) {
  const std::string xml = xml_text.empty() ? read_file(home) : xml_text;
  std::vector<ZipEntry> entries{{home.filename().string(), xml}};
  std::set<std::string> added;
  for (const std::string& model : sweet_home_model_names(xml)) {
    const fs::path file = home.parent_path() / "furniture" / base_name(model);
    if (!fs::exists(file) || !added.insert(file.filename().string()).second) continue;
    std::string obj = read_file(file);
    for (const std::string& mtl : obj_material_libraries(obj)) {
      if (added.insert(mtl).second) entries.push_back({"furniture/" + mtl, read_file(file.parent_path() / mtl)});
    }
    entries.push_back({"furniture/" + file.filename().string(), std::move(obj)});
  }
  return make_zip(entries);
}

std::string moved_sweet_home(const std::string& xml, double dx_cm, double dy_cm) {
  static const std::regex tag(R"(<([A-Za-z]+)\b[^>]*>)");
  static const std::regex coordinate(R"re((\s)(x|y|xStart|yStart|xEnd|yEnd)=(['"])([^'"]*)\3)re");
  std::string out;
  auto last = xml.cbegin();
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), tag); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    out.append(last, m[0].first);
    last = m[0].second;
    const std::string name = m[1].str(), text = m[0].str();
    if (name == "lightSource" || name == "sash") {
      out += text;
      continue;
    }
    std::string moved;
    auto from = text.cbegin();
    for (auto a = std::sregex_iterator(text.begin(), text.end(), coordinate); a != std::sregex_iterator(); ++a) {
      const std::smatch& attr = *a;
      moved.append(from, attr[0].first);
      from = attr[0].second;
      const bool is_x = attr[2].str().front() == 'x';
      moved += attr[1].str() + attr[2].str() + "=" + attr[3].str() + shifted(attr[4].str(), is_x ? dx_cm : dy_cm) +
               attr[3].str();
    }
    moved.append(from, text.cend());
    out += moved;
  }
  out.append(last, xml.cend());
  return out;
}

DistinctHome distinct_sweet_home(size_t i) {
  static std::mutex mutex;
  static std::map<size_t, DistinctHome> made;  // zipping is slow next to a test's other work
  std::lock_guard lock(mutex);
  if (auto it = made.find(i); it != made.end()) return it->second;
  const std::vector<fs::path> homes = sweet_home_files();
  if (homes.empty()) throw std::runtime_error("../shared/data is absent");
  const fs::path& home = homes[i % homes.size()];
  const size_t round = i / homes.size();
  DistinctHome out;
  out.name = home.stem().string() + (round ? "+" + std::to_string(round) : "");
  out.zip = sweet_home_zip(home, round ? moved_sweet_home(read_file(home), 5000.0 * double(round), 0.0) : "");
  made.emplace(i, out);
  return out;
}

}  // namespace rr::testing
