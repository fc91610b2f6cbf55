// Shared by the integration tests of the HTTP service: a real Service on a free loopback port
// (in-process), httplib clients, raw-socket exchanges for requests a well-behaved client cannot
// send, problem+json checks, PNG header reading, and a log sink that keeps the service's lines.
#pragma once

#include "server/http_server.hpp"
#include "support/test_support.hpp"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <sys/types.h>

#include <cstdio>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace rr::testing {

// A config for tests: any free port, 8 connection threads, quiet logs.
rr::server::ServerConfig test_server_config();

// Collects the service's log lines (set it as config.log_sink via sink()).
class LogCapture {
 public:
  std::function<void(const std::string&)> sink();
  std::vector<nlohmann::json> lines() const;

 private:
  std::shared_ptr<std::mutex> mutex_ = std::make_shared<std::mutex>();
  std::shared_ptr<std::vector<std::string>> lines_ = std::make_shared<std::vector<std::string>>();
};

// A started Service and clients for it.
class TestServer {
 public:
  explicit TestServer(rr::server::ServerConfig config = test_server_config());
  int port() const { return service_->port(); }
  rr::server::Service& service() { return *service_; }
  httplib::Client client(int read_timeout_s = 30) const;
  // The metric's value, summed over series whose labels contain every given `label="value"` pair.
  double metric(const std::string& name, const std::vector<std::string>& labels = {}) const;
  void stop() { service_->stop(); }

 private:
  std::unique_ptr<rr::server::Service> service_;
};

// The base of a test suite whose tests share one server: started before the suite's first test with
// Suite::config() (test_server_config() unless the suite declares its own), stopped after its last.
//   class StoreTest : public SharedServerTest<StoreTest> {};
template <class Suite>
class SharedServerTest : public ::testing::Test {
 protected:
  static rr::server::ServerConfig config() { return test_server_config(); }
  static void SetUpTestSuite() { server_ = std::make_unique<TestServer>(Suite::config()); }
  static void TearDownTestSuite() { server_.reset(); }
  static httplib::Client client() { return server_->client(); }

  static inline std::unique_ptr<TestServer> server_;
};

// Checks the problem+json shape (type, title, status, detail) and returns the body.
nlohmann::json expect_problem(const httplib::Result& res, int status);
// expect_problem, and the answer carries `header: value` (Allow with 405, Retry-After with 503).
void expect_problem_with(const httplib::Result& res, int status, const std::string& header, const std::string& value);
void expect_healthy(const TestServer& server);

struct PngSize {
  uint32_t width = 0, height = 0;
};
// The PNG signature, then the IHDR chunk's big-endian width and height (PNG spec section 11.2.2).
PngSize png_size(const std::string& png);

// `roomrender serve ARGS` (the built binary) in a process of its own, its stdout read through `out`,
// and the port its "listening" line names (0 when it printed none: it failed to start).
struct ServerProcess {
  pid_t pid = -1;
  std::FILE* out = nullptr;
  int port = 0;
};
ServerProcess start_server_process(const std::vector<std::string>& args);

// Sends raw bytes and reads until the server closes the connection (or 10 s pass).
std::string raw_exchange(int port, const std::string& request);
// A connected loopback TCP socket (or -1).
int connect_loopback(int port);

// A small, quick request: a floor and a box, 64x48.
extern const char* const small_request;
// small_request's scene with its box moved to x (metres): a distinct scene id per x.
nlohmann::json scene_with_box_at(double x);
// POST /v1/scenes of `scene`.
httplib::Result post_scene(const TestServer& server, const nlohmann::json& scene, const httplib::Headers& headers = {});

std::string base64_decode(const std::string& text);

}  // namespace rr::testing
