// SceneStore (see scene_store.hpp). Files are written with POSIX calls because the crash-safety
// argument needs fsync of the file before the rename and of the directory after it, which iostreams
// cannot express.
#include "server/scene_store.hpp"

#include "server/http_util.hpp"
#include "render/core/scene_id.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace rr::server {

namespace fs = std::filesystem;

namespace {

// Approximate heap cost of an entry: the text, the parsed scene (about as large as its text, in
// practice smaller), and the tessellation's arrays.
size_t entry_bytes(const StoredScene& s) {
  size_t bytes = sizeof(StoredScene) + 2 * s.text.size();
  bytes += s.soup.positions.capacity() * sizeof(Vec3) + s.soup.normals.capacity() * sizeof(glm::vec3);
  bytes += s.soup.polygons.capacity() * sizeof(Polygon) + s.soup.materials.capacity() * sizeof(Material);
  bytes += s.soup.objects.capacity() * sizeof(SceneObject) + s.warnings.capacity() * sizeof(PlacementWarning);
  return bytes;
}

void write_all(int fd, const std::string& bytes, const std::string& path) {
  size_t done = 0;
  while (done < bytes.size()) {
    ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw std::runtime_error("cannot write " + path + ": " + std::strerror(errno));
    done += size_t(n);
  }
}

void fsync_path(const fs::path& path, int flags) {
  int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot open " + path.string() + ": " + std::strerror(errno));
  int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) throw std::runtime_error("cannot fsync " + path.string() + ": " + std::strerror(errno));
}

std::string read_whole(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw std::runtime_error("cannot read " + path.string());
  return text.str();
}

const std::regex id_pattern("[0-9a-f]{16}");

}  // namespace

std::string scene_document_pointer(const std::string& request_pointer) {
  if (request_pointer == "/scene") return "";
  if (request_pointer.starts_with("/scene/")) return request_pointer.substr(6);
  return request_pointer;
}

std::shared_ptr<const StoredScene> prepare_scene(const nlohmann::json& document, const ParseLimits& limits) {
  RenderRequest parsed;
  try {
    parsed = request_from_json(nlohmann::json{{"scene", document}}, limits);
  } catch (const InputError& e) {
    throw e.with_pointers(scene_document_pointer);
  }
  auto out = std::make_shared<StoredScene>();
  out->text = document.dump();
  out->id = hash_hex(out->text);
  static_cast<PreparedScene&>(*out) = rr::prepare_scene(std::move(parsed.scene));
  out->bytes = entry_bytes(*out);
  return out;
}

SceneStore::SceneStore(SceneStoreConfig config, Log log)
    : config_(std::move(config)), log_(std::move(log)), cache_(config_.max_bytes, config_.max_entries) {
  cache_.set_eviction_listener([this](const std::string& id) {
    if (!config_.data_dir.empty()) {
      std::error_code ec;
      fs::remove(file_for(id), ec);
    }
    log_("info", {{"event", "scene_evicted"}, {"scene", id}});
  });
}

fs::path SceneStore::file_for(const std::string& id) const { return config_.data_dir / "scenes" / (id + ".json"); }

void SceneStore::write_file(const StoredScene& scene) const {
  const fs::path final_path = file_for(scene.id);
  const fs::path temp_path = final_path.parent_path() / (".tmp-" + scene.id);  // writes are serialised
  int fd = ::open(temp_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot create " + temp_path.string() + ": " + std::strerror(errno));
  try {
    write_all(fd, scene.text, temp_path.string());
    if (::fsync(fd) != 0) throw std::runtime_error("cannot fsync " + temp_path.string() + ": " + std::strerror(errno));
  } catch (...) {
    ::close(fd);
    ::unlink(temp_path.c_str());
    throw;
  }
  ::close(fd);
  if (::rename(temp_path.c_str(), final_path.c_str()) != 0) {
    ::unlink(temp_path.c_str());
    throw std::runtime_error("cannot rename to " + final_path.string() + ": " + std::strerror(errno));
  }
  fsync_path(final_path.parent_path(), O_RDONLY | O_DIRECTORY);  // makes the rename itself durable
}

size_t SceneStore::load() {
  if (config_.data_dir.empty()) return 0;
  const fs::path dir = config_.data_dir / "scenes";
  fs::create_directories(dir);
  std::vector<std::pair<fs::file_time_type, fs::path>> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with(".tmp-")) {  // a write that a crash interrupted before its rename
      std::error_code ec;
      fs::remove(entry.path(), ec);
      log_("warn", {{"event", "scene_temp_removed"}, {"file", entry.path().string()}});
    } else if (entry.is_regular_file() && entry.path().extension() == ".json" &&
               std::regex_match(entry.path().stem().string(), id_pattern)) {
      files.emplace_back(entry.last_write_time(), entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  size_t loaded = 0;
  for (const auto& [time, path] : files) {
    try {
      auto scene = prepare_scene(parse_json_text(read_whole(path), config_.limits), config_.limits);
      if (scene->id != path.stem().string()) {
        throw std::runtime_error("content hashes to " + scene->id + ", not to its file name");
      }
      std::lock_guard lock(mutation_);
      if (cache_.put(scene->id, scene, scene->bytes)) ++loaded;
    } catch (const std::exception& e) {  // kept on disk for a person to look at; not served
      log_("warn", {{"event", "scene_file_skipped"}, {"file", path.string()}, {"reason", e.what()}});
    }
  }
  return loaded;
}

SceneStore::PutResult SceneStore::put(const std::shared_ptr<const StoredScene>& scene) {
  std::lock_guard lock(mutation_);
  if (auto held = cache_.find(scene->id)) return held->text == scene->text ? PutResult::existed : PutResult::conflict;
  if (scene->bytes > config_.max_bytes) return PutResult::too_large;
  if (!config_.data_dir.empty()) write_file(*scene);
  cache_.put(scene->id, scene, scene->bytes);
  return PutResult::created;
}

std::shared_ptr<const StoredScene> SceneStore::find(const std::string& id) { return cache_.find(id); }

bool SceneStore::erase(const std::string& id) {
  std::lock_guard lock(mutation_);
  bool removed = cache_.erase(id);
  if (removed && !config_.data_dir.empty()) {
    std::error_code ec;
    fs::remove(file_for(id), ec);
  }
  return removed;
}

}  // namespace rr::server
