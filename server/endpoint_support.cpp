// What every endpoint file shares (declared in routes.hpp): the service state, the per-request
// context, JSON answers and times, conditional requests, body parsing and render admission.
#include "server/routes.hpp"

#include "server/catalogue_store.hpp"
#include "server/http_util.hpp"
#include "server/problem.hpp"

#include <httplib.h>

#include <cstdio>
#include <ctime>

namespace rr::server {

namespace {

int level_rank(const std::string& level) {
  if (level == "info") return 1;
  if (level == "warn") return 2;
  if (level == "error") return 3;
  return 4;  // off
}

// Gives free heap pages back to the OS when the work it times (from start(), so not the queue wait)
// ran at least `threshold_ms`: glibc
// keeps what a large render freed (its arenas grow per thread and shrink only from the top), so a
// burst of heavy renders would otherwise leave the process hundreds of MiB above its idle size.
// Declared before the render slot, it asks for the trim when the slot is released, also when the
// work threw (a render cancelled at its deadline has allocated as much as one that finished); the
// trim itself runs after the answer is written (log_request), so no client waits for it.
class TrimAfterLargeWork {
 public:
  explicit TrimAfterLargeWork(int threshold_ms) : threshold_ms_(threshold_ms) {}
  TrimAfterLargeWork(const TrimAfterLargeWork&) = delete;
  TrimAfterLargeWork& operator=(const TrimAfterLargeWork&) = delete;
  ~TrimAfterLargeWork() {
    if (started_ && threshold_ms_ >= 0 && clock_.elapsed_ms() >= double(threshold_ms_)) {
      request_context().trim_heap_after_response = true;
    }
  }
  void start() {
    clock_ = Stopwatch();
    started_ = true;
  }

 private:
  int threshold_ms_;
  bool started_ = false;
  Stopwatch clock_;
};

// "2026-12-02T04:00:00.123Z" (RFC 3339, UTC).
std::string rfc3339(std::chrono::system_clock::time_point t) {
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(t.time_since_epoch()).count();
  std::time_t seconds = std::time_t(ms / 1000);
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char text[40];
  size_t n = std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
  std::snprintf(text + n, sizeof text - n, ".%03dZ", int(ms % 1000));
  return text;
}

}  // namespace

namespace {

ServerConfig with_catalogue(ServerConfig config, const std::shared_ptr<const Catalogue>& catalogue) {
  config.limits = catalogue_limits(config.limits, catalogue);
  return config;
}

Stores with_catalogue(Stores stores, const std::shared_ptr<const Catalogue>& catalogue) {
  stores.meshes = std::make_unique<CatalogueMeshes>(std::move(stores.meshes), catalogue, catalogue->meshes);
  stores.textures = std::make_unique<CatalogueImages>(std::move(stores.textures), catalogue, catalogue->images);
  return stores;
}

}  // namespace

ServiceState::ServiceState(const ServerConfig& c)
    : catalogue(load_catalogue(c.catalogue_dir, c.limits)),
      config(with_catalogue(c, catalogue)),
      gate(render_workers(c), render_queue_length(c)),
      workers(render_workers(c)),
      stores(
          with_catalogue(open_stores(config, [this](const std::string& level,
                                                    nlohmann::ordered_json fields) { log(level, std::move(fields)); }),
                         catalogue)),
      cache(config, stores),
      limits(cache.limits()),
      access{c.cors_origins, TokenTable::load(c.api_token_file), c.allow_listing} {}

void ServiceState::log(const std::string& level, nlohmann::ordered_json fields) const {
  if (level_rank(level) < level_rank(config.log_level)) return;
  nlohmann::ordered_json line = {{"level", level}};
  line.update(fields);
  std::string text = line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  if (config.log_sink) {
    config.log_sink(text);
  } else {
    text += '\n';
    std::fwrite(text.data(), 1, text.size(), stderr);  // one write per line keeps lines whole
  }
}

RequestContext& request_context() {
  thread_local RequestContext context;
  return context;
}

nlohmann::json time_or_null(const std::optional<std::chrono::system_clock::time_point>& t) {
  return t ? nlohmann::json(rfc3339(*t)) : nlohmann::json(nullptr);
}

void send_json(httplib::Response& res, const nlohmann::json& body, int status) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

bool answer_not_modified(const httplib::Request& req, httplib::Response& res, const std::string& etag) {
  res.set_header("ETag", etag);
  if (!req.has_header("If-None-Match") || !if_none_match_matches(req.get_header_value("If-None-Match"), etag)) {
    return false;
  }
  res.status = 304;
  return true;
}

void send_stored_document(const httplib::Request& req, httplib::Response& res, const std::string& id,
                          const std::string& text, std::string_view media_type) {
  res.set_header("Cache-Control", "public, max-age=31536000, immutable");
  if (answer_not_modified(req, res, "\"" + id + "\"")) return;
  res.set_content(text, std::string(media_type));
}

std::optional<std::string> releasing_owner(const ServiceState& state) {
  if (state.access.tokens.empty()) return std::nullopt;
  return request_context().owner;
}

nlohmann::json parse_body(const ServiceState& state, const httplib::Request& req) {
  return parse_json_text(req.body, state.config.limits);
}

void require_admission(ServiceState& state, RenderGate::Admission admission) {
  using Admission = RenderGate::Admission;
  if (admission == Admission::admitted) return;
  HeaderList retry = {{"Retry-After", std::to_string(state.config.retry_after_s)}};
  switch (admission) {
    case Admission::saturated:
      state.metrics.record_rejection("saturated");
      throw HttpError(503, "Every render slot is busy and the queue is full; retry shortly.", {}, retry);
    case Admission::expired:
      state.metrics.record_rejection("expired");
      throw HttpError(503,
                      "The render waited in the queue past its deadline of " +
                          std::to_string(state.config.render_timeout_ms) + " ms; retry shortly.",
                      {}, retry);
    default:
      state.metrics.record_rejection("draining");
      throw HttpError(503, "The server is shutting down and takes no new renders.", {}, retry);
  }
}

void with_render_slot(ServiceState& state, const std::function<void(const CancelToken&, SlotClock&)>& work) {
  TrimAfterLargeWork trim(state.config.trim_after_work_ms);
  CancelToken token;
  token.deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(state.config.render_timeout_ms);
  Stopwatch queue;
  GateSlot slot(state.gate, token);
  const double queue_ms = queue.elapsed_ms();
  require_admission(state, slot.admission());
  if (state.config.on_render_admitted) state.config.on_render_admitted();
  trim.start();
  SlotClock total;
  total.queue_ms = queue_ms;
  try {
    work(token, total);
  } catch (const RenderCancelled&) {
    if (token.cancelled.load()) {
      state.metrics.record_rejection("draining");
      throw HttpError(503, "The server is shutting down and stopped this render; retry later.", {},
                      {{"Retry-After", std::to_string(state.config.retry_after_s)}});
    }
    state.metrics.record_rejection("deadline");
    throw HttpError(504, "The render did not finish within the deadline of " +
                             std::to_string(state.config.render_timeout_ms) + " ms.");
  }
}

}  // namespace rr::server
