// SceneStore (see scene_store.hpp). Files are written with POSIX calls because the crash-safety
// argument needs fsync of the file before the rename and of the directory after it, which iostreams
// cannot express.
#include "server/scene_store.hpp"

#include "server/http_util.hpp"
#include "render/core/scene_id.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <limits>
#include <tuple>
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

// Writes `text` to a temporary file beside `final_path`, fsyncs it, renames it over `final_path` and
// fsyncs the directory (which makes the rename itself durable). Writers are serialised, so one
// temporary name per file suffices.
void write_atomically(const fs::path& final_path, const std::string& text) {
  const fs::path temp_path = final_path.parent_path() / (".tmp-" + final_path.filename().string());
  int fd = ::open(temp_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot create " + temp_path.string() + ": " + std::strerror(errno));
  try {
    write_all(fd, text, temp_path.string());
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
  fsync_path(final_path.parent_path(), O_RDONLY | O_DIRECTORY);
}

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

SceneStore::SceneStore(SceneStoreConfig config, Log log) : config_(std::move(config)), log_(std::move(log)) {}

fs::path SceneStore::file_for(const std::string& id) const { return config_.data_dir / "scenes" / (id + ".json"); }
fs::path SceneStore::meta_for(const std::string& id) const { return config_.data_dir / "scene-meta" / (id + ".json"); }

void SceneStore::write_meta(const std::string& id, int64_t created_us, const std::set<std::string>& owners) const {
  write_atomically(meta_for(id), nlohmann::json{{"created_us", created_us}, {"owners", owners}}.dump());
}

// The scene first, then its metadata: a crash in between leaves metadata alone, which load() removes.
void SceneStore::remove_files(const std::string& id) const {
  if (config_.data_dir.empty()) return;
  std::error_code ec;
  fs::remove(file_for(id), ec);
  fs::remove(meta_for(id), ec);
}

bool SceneStore::expired(const Entry& entry, Clock::time_point now) const {
  return config_.ttl.count() > 0 && now - entry.last_access >= config_.ttl;
}

int64_t SceneStore::next_created_us(Clock::time_point now) {
  int64_t us = std::chrono::duration_cast<std::chrono::microseconds>(now.time_since_epoch()).count();
  last_created_us_ = std::max(us, last_created_us_ + 1);
  return last_created_us_;
}

// Removes every scene whose retention ran out; at most once a second unless forced (a full store
// looks for room first).
void SceneStore::expire(Clock::time_point now, bool force) {
  if (config_.ttl.count() == 0 || (!force && now - last_sweep_ < std::chrono::seconds(1))) return;
  last_sweep_ = now;
  std::vector<std::string> gone;
  {
    std::lock_guard lock(mutex_);
    for (auto it = entries_.begin(); it != entries_.end();) {
      if (!expired(it->second, now)) {
        ++it;
        continue;
      }
      gone.push_back(it->first);
      bytes_ -= it->second.scene->bytes;
      it = entries_.erase(it);
    }
  }
  for (const std::string& id : gone) {
    remove_files(id);
    log_("info", {{"event", "scene_expired"}, {"scene", id}});
  }
}

std::optional<SceneStore::Clock::time_point> SceneStore::expiry_from_now() const {
  if (config_.ttl.count() == 0) return std::nullopt;
  return Clock::now() + config_.ttl;
}

size_t SceneStore::load() {
  if (config_.data_dir.empty()) return 0;
  std::lock_guard write(mutation_);
  for (const char* sub : {"scenes", "scene-meta"}) {
    fs::create_directories(config_.data_dir / sub);
    for (const auto& entry : fs::directory_iterator(config_.data_dir / sub)) {
      if (!entry.path().filename().string().starts_with(".tmp-")) continue;
      std::error_code ec;  // a write that a crash interrupted before its rename
      fs::remove(entry.path(), ec);
      log_("warn", {{"event", "scene_temp_removed"}, {"file", entry.path().string()}});
    }
  }
  for (const auto& entry : fs::directory_iterator(config_.data_dir / "scene-meta")) {
    if (!fs::exists(file_for(entry.path().stem().string()))) {  // its scene's removal was interrupted
      std::error_code ec;
      fs::remove(entry.path(), ec);
    }
  }
  std::vector<std::pair<fs::file_time_type, fs::path>> files;
  for (const auto& entry : fs::directory_iterator(config_.data_dir / "scenes")) {
    if (entry.is_regular_file() && entry.path().extension() == ".json" &&
        std::regex_match(entry.path().stem().string(), id_pattern)) {
      files.emplace_back(entry.last_write_time(), entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  size_t loaded = 0;
  for (const auto& [time, path] : files) {
    try {
      loaded += load_one(path, std::chrono::file_clock::to_sys(time));
    } catch (const std::exception& e) {  // kept on disk for a person to look at; not served
      log_("warn", {{"event", "scene_file_skipped"}, {"file", path.string()}, {"reason", e.what()}});
    }
  }
  if (entries_.size() > config_.max_entries || bytes_ > config_.max_bytes) {
    log_("warn", {{"event", "scene_store_over_budget"}, {"entries", entries_.size()}, {"bytes", bytes_},
                  {"max_entries", config_.max_entries}, {"max_bytes", config_.max_bytes}});
  }
  return loaded;
}

// One scene file and its metadata (a file without metadata predates owners: it belongs to "", the
// owner of a server without tokens, and was created when last written).
bool SceneStore::load_one(const fs::path& path, Clock::time_point modified) {
  auto scene = prepare_scene(parse_json_text(read_whole(path), config_.limits), config_.limits);
  if (scene->id != path.stem().string()) {
    throw std::runtime_error("content hashes to " + scene->id + ", not to its file name");
  }
  Entry entry{scene, {""}, 0, modified, modified};
  entry.created_us = std::chrono::duration_cast<std::chrono::microseconds>(modified.time_since_epoch()).count();
  if (fs::exists(meta_for(scene->id))) {
    nlohmann::json meta = nlohmann::json::parse(read_whole(meta_for(scene->id)));
    entry.created_us = meta.at("created_us").get<int64_t>();
    entry.owners = meta.at("owners").get<std::set<std::string>>();
  }
  if (expired(entry, Clock::now())) {
    remove_files(scene->id);
    log_("info", {{"event", "scene_expired"}, {"scene", scene->id}});
    return false;
  }
  std::lock_guard lock(mutex_);
  last_created_us_ = std::max(last_created_us_, entry.created_us);
  bytes_ += scene->bytes;
  return entries_.emplace(scene->id, std::move(entry)).second;
}

SceneStore::PutResult SceneStore::put(const std::shared_ptr<const StoredScene>& scene, const std::string& owner) {
  std::lock_guard write(mutation_);
  const Clock::time_point now = Clock::now();
  expire(now, false);
  std::unique_lock lock(mutex_);
  auto it = entries_.find(scene->id);
  if (it != entries_.end() && expired(it->second, now)) {  // gone, though not swept yet
    lock.unlock();
    expire(now, true);
    lock.lock();
    it = entries_.find(scene->id);
  }
  if (it != entries_.end()) {
    Entry& held = it->second;  // stays put: only writers erase, and this is the writer
    if (held.scene->text != scene->text) return PutResult::conflict;
    held.last_access = now;
    lock.unlock();
    if (!held.owners.contains(owner)) {
      std::set<std::string> owners = held.owners;
      owners.insert(owner);
      if (!config_.data_dir.empty()) write_meta(scene->id, held.created_us, owners);
      held.owners = std::move(owners);
    }
    return PutResult::existed;
  }
  if (scene->bytes > config_.max_bytes) return PutResult::too_large;
  auto fits = [&] { return entries_.size() < config_.max_entries && bytes_ + scene->bytes <= config_.max_bytes; };
  if (!fits()) {
    lock.unlock();
    expire(now, true);
    lock.lock();
    if (!fits()) return PutResult::full;
  }
  Entry entry{scene, {owner}, next_created_us(now), now, now};
  lock.unlock();
  // Metadata first: a scene file is never there without its owners. A scene of a server without
  // tokens or retention needs none (no file means owner "" created at the file's time), which
  // keeps such a store at one file, and half the fsyncs, per scene.
  const bool with_meta = !owner.empty() || config_.ttl.count() > 0;
  if (!config_.data_dir.empty()) {
    if (with_meta) write_meta(scene->id, entry.created_us, entry.owners);
    try {
      write_atomically(file_for(scene->id), scene->text);
    } catch (...) {
      std::error_code ec;
      if (with_meta) fs::remove(meta_for(scene->id), ec);
      throw;
    }
  }
  lock.lock();
  bytes_ += scene->bytes;
  entries_.emplace(scene->id, std::move(entry));
  return PutResult::created;
}

std::shared_ptr<const StoredScene> SceneStore::find(const std::string& id) {
  const Clock::time_point now = Clock::now();
  std::shared_ptr<const StoredScene> scene;
  bool persist_access = false;
  {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(id);
    if (it == entries_.end() || expired(it->second, now)) {
      ++stats_.misses;
      return nullptr;
    }
    ++stats_.hits;
    Entry& entry = it->second;
    entry.last_access = now;
    scene = entry.scene;
    // The file's time is the access a restart resumes retention from; moved on now and then, not
    // on every read (an eighth of the retention, at most a minute, late is close enough).
    auto interval = std::min<Clock::duration>(std::chrono::minutes(1), Clock::duration(config_.ttl) / 8);
    if (config_.ttl.count() > 0 && !config_.data_dir.empty() && now - entry.persisted_access >= interval) {
      entry.persisted_access = now;
      persist_access = true;
    }
  }
  if (persist_access) {
    std::error_code ec;  // a file removed meanwhile has no time to keep
    fs::last_write_time(file_for(id), std::chrono::file_clock::from_sys(now), ec);
  }
  return scene;
}

SceneStore::ReleaseResult SceneStore::release(const std::string& id, const std::optional<std::string>& owner) {
  std::lock_guard write(mutation_);
  const Clock::time_point now = Clock::now();
  expire(now, false);
  Entry* entry = nullptr;
  {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(id);
    if (it == entries_.end() || expired(it->second, now)) return ReleaseResult::not_found;
    entry = &it->second;
  }
  if (owner && !entry->owners.contains(*owner)) return ReleaseResult::not_owner;
  if (owner && entry->owners.size() > 1) {
    std::set<std::string> owners = entry->owners;
    owners.erase(*owner);
    if (!config_.data_dir.empty()) write_meta(id, entry->created_us, owners);
    entry->owners = std::move(owners);
    return ReleaseResult::reference_dropped;
  }
  {
    std::lock_guard lock(mutex_);
    bytes_ -= entry->scene->bytes;
    entries_.erase(id);
  }
  remove_files(id);
  return ReleaseResult::removed;
}

SceneStore::Page SceneStore::list(const std::optional<std::string>& owner, size_t limit, const std::string& cursor) {
  // A cursor is "<created_us>-<id>" of the last scene of the previous page.
  std::pair<int64_t, std::string> after{std::numeric_limits<int64_t>::max(), ""};
  if (!cursor.empty()) {
    size_t dash = cursor.find('-');
    auto [end, ec] = std::from_chars(cursor.data(), cursor.data() + dash, after.first);
    if (dash == std::string::npos || ec != std::errc() || end != cursor.data() + dash ||
        !std::regex_match(cursor.substr(dash + 1), id_pattern)) {
      throw std::invalid_argument("not a cursor of this listing");
    }
    after.second = cursor.substr(dash + 1);
  }
  std::lock_guard write(mutation_);
  const Clock::time_point now = Clock::now();
  expire(now, false);
  std::vector<Listed> all;
  {
    std::lock_guard lock(mutex_);
    for (const auto& [id, entry] : entries_) {
      if (expired(entry, now) || (owner && !entry.owners.contains(*owner))) continue;
      if (std::pair(entry.created_us, id) >= after && !cursor.empty()) continue;
      std::optional<Clock::time_point> expires;
      if (config_.ttl.count() > 0) expires = entry.last_access + config_.ttl;
      all.push_back({id, entry.created_us, expires, entry.scene->bytes});
    }
  }
  std::sort(all.begin(), all.end(), [](const Listed& a, const Listed& b) {
    return std::tie(a.created_us, a.id) > std::tie(b.created_us, b.id);
  });
  Page page;
  if (all.size() > limit) {
    all.resize(limit);
    page.next_cursor = std::to_string(all.back().created_us) + "-" + all.back().id;
  }
  page.scenes = std::move(all);
  return page;
}

CacheStats SceneStore::stats() {
  {
    std::lock_guard write(mutation_);
    expire(Clock::now(), false);
  }
  std::lock_guard lock(mutex_);
  CacheStats s = stats_;
  s.bytes = bytes_;
  s.entries = entries_.size();
  s.budget_bytes = config_.max_bytes;
  s.max_entries = config_.max_entries;
  return s;
}

}  // namespace rr::server
