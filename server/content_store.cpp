// ContentStore (see content_store.hpp), instantiated for scenes, meshes and images at the end. Files are
// written with POSIX calls because the crash-safety argument needs fsync of the file before the
// rename and of the directory after it, which iostreams cannot express.
#include "server/content_store.hpp"

#include "server/mesh_store.hpp"
#include "server/scene_store.hpp"
#include "server/texture_store.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <limits>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <tuple>
#include <vector>

namespace rr::server {

namespace fs = std::filesystem;

namespace {

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

// The file's content, or nullopt when there is no such file (removed by a writer meanwhile).
std::optional<std::string> read_if_there(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
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

template <class T>
ContentStore<T>::ContentStore(Config config, Log log) : config_(std::move(config)), log_(std::move(log)) {}

template <class T>
fs::path ContentStore<T>::file_for(const std::string& id) const {
  return config_.data_dir / config_.plural / (id + config_.extension);
}
template <class T>
fs::path ContentStore<T>::meta_for(const std::string& id) const {
  return config_.data_dir / (config_.kind + "-meta") / (id + ".json");
}

template <class T>
void ContentStore<T>::write_meta(const std::string& id, int64_t created_us, const std::set<std::string>& owners) const {
  write_atomically(meta_for(id), nlohmann::json{{"created_us", created_us}, {"owners", owners}}.dump());
}

// The content first, then its metadata: a crash in between leaves metadata alone, which load() removes.
template <class T>
void ContentStore<T>::remove_files(const std::string& id) const {
  if (config_.data_dir.empty()) return;
  std::error_code ec;
  fs::remove(file_for(id), ec);
  fs::remove(meta_for(id), ec);
}

template <class T>
bool ContentStore<T>::expired(const std::string& id, const Entry& entry, Clock::time_point now) const {
  if (config_.ttl.count() == 0 || now - entry.last_access < config_.ttl) return false;
  return !(config_.pinned && config_.pinned(id));  // a pinned entry outlives its ttl
}

template <class T>
std::optional<std::string> ContentStore<T>::read_text(const Entry& entry, const std::string& id) const {
  if (entry.text) return *entry.text;
  return read_if_there(file_for(id));
}

template <class T>
int64_t ContentStore<T>::next_created_us(Clock::time_point now) {
  int64_t us = std::chrono::duration_cast<std::chrono::microseconds>(now.time_since_epoch()).count();
  last_created_us_ = std::max(us, last_created_us_ + 1);
  return last_created_us_;
}

// Removes every item whose retention ran out; at most once a second unless forced (a full store
// looks for room first).
template <class T>
void ContentStore<T>::expire(Clock::time_point now, bool force) {
  if (config_.ttl.count() == 0 || (!force && now - last_sweep_ < std::chrono::seconds(1))) return;
  last_sweep_ = now;
  std::vector<std::tuple<std::string, std::vector<std::string>, std::vector<std::string>>> gone;  // id, meshes, images
  {
    std::lock_guard lock(mutex_);
    for (auto it = entries_.begin(); it != entries_.end();) {
      if (!expired(it->first, it->second, now)) {
        ++it;
        continue;
      }
      gone.emplace_back(it->first, std::move(it->second.refs), std::move(it->second.texture_refs));
      bytes_ -= it->second.bytes;
      it = entries_.erase(it);
    }
  }
  for (const auto& [id, refs, texture_refs] : gone) {
    remove_files(id);
    if (config_.on_change) config_.on_change(id, refs, texture_refs, false);
    log_("info", {{"event", config_.kind + "_expired"}, {config_.kind, id}});
  }
}

template <class T>
std::optional<typename ContentStore<T>::Clock::time_point> ContentStore<T>::expiry_from_now() const {
  if (config_.ttl.count() == 0) return std::nullopt;
  return Clock::now() + config_.ttl;
}

template <class T>
size_t ContentStore<T>::load() {
  if (config_.data_dir.empty()) return 0;
  std::lock_guard write(mutation_);
  for (const std::string& sub : {config_.plural, config_.kind + "-meta"}) {
    fs::create_directories(config_.data_dir / sub);
    for (const auto& entry : fs::directory_iterator(config_.data_dir / sub)) {
      if (!entry.path().filename().string().starts_with(".tmp-")) continue;
      std::error_code ec;  // a write that a crash interrupted before its rename
      fs::remove(entry.path(), ec);
      log_("warn", {{"event", config_.kind + "_temp_removed"}, {"file", entry.path().string()}});
    }
  }
  for (const auto& entry : fs::directory_iterator(config_.data_dir / (config_.kind + "-meta"))) {
    if (!fs::exists(file_for(entry.path().stem().string()))) {  // its item's removal was interrupted
      std::error_code ec;
      fs::remove(entry.path(), ec);
    }
  }
  std::vector<std::pair<fs::file_time_type, fs::path>> files;
  for (const auto& entry : fs::directory_iterator(config_.data_dir / config_.plural)) {
    if (entry.is_regular_file() && entry.path().extension() == config_.extension &&
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
      log_("warn", {{"event", config_.kind + "_file_skipped"}, {"file", path.string()}, {"reason", e.what()}});
    }
  }
  if (entries_.size() > config_.max_entries || bytes_ > config_.max_bytes) {
    log_("warn", {{"event", config_.kind + "_store_over_budget"},
                  {"entries", entries_.size()},
                  {"bytes", bytes_},
                  {"max_entries", config_.max_entries},
                  {"max_bytes", config_.max_bytes}});
  }
  return loaded;
}

// One document file and its metadata (a file without metadata predates owners: it belongs to "",
// the owner of a server without tokens, and was created when last written). Only its index entry
// stays in memory; what is prepared from it is built when first wanted (prepared_cache.hpp).
template <class T>
bool ContentStore<T>::load_one(const fs::path& path, Clock::time_point modified) {
  const std::string text = read_whole(path);
  StoredDocument document = config_.read(text);
  const std::string id = path.stem().string();
  if (document.id != id) throw std::runtime_error("content hashes to " + document.id + ", not to its file name");
  Entry entry{text.size(), std::move(document.refs), std::move(document.texture_refs), nullptr, {""}, 0, modified,
              modified};
  entry.created_us = std::chrono::duration_cast<std::chrono::microseconds>(modified.time_since_epoch()).count();
  if (fs::exists(meta_for(id))) {
    nlohmann::json meta = nlohmann::json::parse(read_whole(meta_for(id)));
    entry.created_us = meta.at("created_us").get<int64_t>();
    entry.owners = meta.at("owners").get<std::set<std::string>>();
  }
  // What pins an entry may load after it (scenes after their meshes): a later sweep decides.
  if (!config_.pinned && expired(id, entry, Clock::now())) {
    remove_files(id);
    log_("info", {{"event", config_.kind + "_expired"}, {config_.kind, id}});
    return false;
  }
  std::lock_guard lock(mutex_);
  last_created_us_ = std::max(last_created_us_, entry.created_us);
  const size_t bytes = entry.bytes;
  auto [it, added] = entries_.emplace(id, std::move(entry));
  if (!added) return false;
  bytes_ += bytes;
  if (config_.on_change) config_.on_change(id, it->second.refs, it->second.texture_refs, true);
  return true;
}

template <class T>
typename ContentStore<T>::PutResult ContentStore<T>::put(const StoredDocument& document, const std::string& owner) {
  const std::string& id = document.id;
  const size_t bytes = document.bytes();
  std::lock_guard write(mutation_);
  const Clock::time_point now = Clock::now();
  expire(now, false);
  std::unique_lock lock(mutex_);
  auto it = entries_.find(id);
  if (it != entries_.end() && expired(id, it->second, now)) {  // gone, though not swept yet
    lock.unlock();
    expire(now, true);
    lock.lock();
    it = entries_.find(id);
  }
  if (it != entries_.end()) {
    Entry& held = it->second;  // stays put: only writers erase, and this is the writer
    lock.unlock();
    // Sizes first: the text (a file read with a data directory) only when they agree.
    if (held.bytes != bytes || read_text(held, id) != document.text) return PutResult::conflict;
    lock.lock();
    held.last_access = now;
    lock.unlock();
    if (!held.owners.contains(owner)) {
      std::set<std::string> owners = held.owners;
      owners.insert(owner);
      if (!config_.data_dir.empty()) write_meta(id, held.created_us, owners);
      held.owners = std::move(owners);
    }
    return PutResult::existed;
  }
  if (bytes > config_.max_bytes) return PutResult::too_large;
  auto fits = [&] { return entries_.size() < config_.max_entries && bytes_ + bytes <= config_.max_bytes; };
  if (!fits()) {
    lock.unlock();
    expire(now, true);
    lock.lock();
    if (!fits()) return PutResult::full;
  }
  Entry entry{bytes, document.refs, document.texture_refs, nullptr, {owner}, next_created_us(now), now, now};
  lock.unlock();
  // Metadata first: a document file is never there without its owners. A document of a server
  // without tokens or retention needs none (no file means owner "" created at the file's time),
  // which keeps such a store at one file, and half the fsyncs, per document.
  const bool with_meta = !owner.empty() || config_.ttl.count() > 0;
  if (config_.data_dir.empty()) {
    entry.text = std::make_shared<const std::string>(document.text);
  } else {
    if (with_meta) write_meta(id, entry.created_us, entry.owners);
    try {
      write_atomically(file_for(id), document.text);
    } catch (...) {
      std::error_code ec;
      if (with_meta) fs::remove(meta_for(id), ec);
      throw;
    }
  }
  lock.lock();
  bytes_ += bytes;
  entries_.emplace(id, std::move(entry));
  lock.unlock();
  if (config_.on_change) config_.on_change(id, document.refs, document.texture_refs, true);
  return PutResult::created;
}

template <class T>
std::optional<std::string> ContentStore<T>::find(const std::string& id, bool with_text) {
  const Clock::time_point now = Clock::now();
  std::shared_ptr<const std::string> text;
  bool persist_access = false;
  {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(id);
    if (it == entries_.end() || expired(id, it->second, now)) {
      ++stats_.misses;
      return std::nullopt;
    }
    ++stats_.hits;
    Entry& entry = it->second;
    entry.last_access = now;
    text = entry.text;
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
  if (!with_text) return std::string();
  if (text) return *text;
  // Read outside the locks, so a slow disk holds up no other reader; a file a writer removed
  // meanwhile is a document no longer stored.
  return read_if_there(file_for(id));
}

template <class T>
typename ContentStore<T>::ReleaseResult ContentStore<T>::release(const std::string& id,
                                                                 const std::optional<std::string>& owner) {
  std::lock_guard write(mutation_);
  const Clock::time_point now = Clock::now();
  expire(now, false);
  Entry* entry = nullptr;
  {
    std::lock_guard lock(mutex_);
    auto it = entries_.find(id);
    if (it == entries_.end() || expired(id, it->second, now)) return ReleaseResult::not_found;
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
  if (config_.pinned && config_.pinned(id)) return ReleaseResult::pinned;
  std::vector<std::string> refs, texture_refs;
  {
    std::lock_guard lock(mutex_);
    refs = std::move(entry->refs);
    texture_refs = std::move(entry->texture_refs);
    bytes_ -= entry->bytes;
    entries_.erase(id);
  }
  remove_files(id);
  if (config_.on_change) config_.on_change(id, refs, texture_refs, false);
  return ReleaseResult::removed;
}

template <class T>
typename ContentStore<T>::Page ContentStore<T>::list(const std::optional<std::string>& owner, size_t limit,
                                                     const std::string& cursor) {
  // A cursor is "<created_us>-<id>" of the last item of the previous page.
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
      if (expired(id, entry, now) || (owner && !entry.owners.contains(*owner))) continue;
      if (std::pair(entry.created_us, id) >= after && !cursor.empty()) continue;
      std::optional<Clock::time_point> expires;
      if (config_.ttl.count() > 0) expires = entry.last_access + config_.ttl;
      all.push_back({id, entry.created_us, expires, entry.bytes});
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

template <class T>
CacheStats ContentStore<T>::stats() {
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

template class ContentStore<StoredScene>;
template class ContentStore<StoredMesh>;
template class ContentStore<StoredTexture>;

}  // namespace rr::server
