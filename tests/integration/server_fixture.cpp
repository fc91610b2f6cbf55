// Helpers for the service's integration tests (see server_fixture.hpp).
#include "server_fixture.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <sstream>

namespace rr::testing {

using nlohmann::json;

const char* const small_request = R"({
  "scene": {"floor": {"cells": [4, 4]},
            "solids": [{"type": "box", "center": [0, 0], "size": [1, 1, 1]}],
            "lights": [{"type": "directional", "direction": [-0.3, -1, -0.2]}]},
  "camera": {"position": [3, 2.5, 4], "target": [0, 0.5, 0]},
  "options": {"width": 64, "height": 48}
})";

ServerProcess start_server_process(const std::vector<std::string>& args) {
  int out_pipe[2];
  ServerProcess child;
  if (::pipe(out_pipe) != 0) return child;
  child.pid = ::fork();
  if (child.pid == 0) {
    ::dup2(out_pipe[1], STDOUT_FILENO);
    ::close(out_pipe[0]);
    std::vector<char*> argv;
    std::string binary = ROOMRENDER_BINARY_DIR "/roomrender";
    argv.push_back(binary.data());
    std::vector<std::string> copy = args;
    for (std::string& a : copy) argv.push_back(a.data());
    argv.push_back(nullptr);
    ::execv(binary.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(out_pipe[1]);
  child.out = ::fdopen(out_pipe[0], "r");
  char line[8192] = {};
  if (std::fgets(line, sizeof line, child.out)) {
    json listening = json::parse(line, nullptr, false);
    if (listening.is_object() && listening.value("event", "") == "listening") child.port = listening.value("port", 0);
  }
  return child;
}

rr::server::ServerConfig test_server_config() {
  rr::server::ServerConfig config = rr::server::default_server_config();
  config.port = 0;
  config.threads = 8;
  config.log_requests = false;
  config.log_level = "off";
  return config;
}

std::function<void(const std::string&)> LogCapture::sink() {
  return [mutex = mutex_, lines = lines_](const std::string& line) {
    std::lock_guard lock(*mutex);
    lines->push_back(line);
  };
}

std::vector<json> LogCapture::lines() const {
  std::lock_guard lock(*mutex_);
  std::vector<json> out;
  for (const std::string& line : *lines_) out.push_back(json::parse(line));
  return out;
}

TestServer::TestServer(rr::server::ServerConfig config)
    : service_(std::make_unique<rr::server::Service>(std::move(config))) {
  service_->start();
}

httplib::Client TestServer::client(int read_timeout_s) const {
  httplib::Client cli("127.0.0.1", service_->port());
  cli.set_connection_timeout(5);
  cli.set_read_timeout(read_timeout_s);
  return cli;
}

double TestServer::metric(const std::string& name, const std::vector<std::string>& labels) const {
  auto res = client().Get("/metrics");
  EXPECT_TRUE(res && res->status == 200);
  if (!res) return -1.0;
  std::istringstream lines(res->body);
  double total = 0.0;
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::string series = line.substr(0, line.rfind(' '));
    std::string metric_name = series.substr(0, series.find('{'));
    if (metric_name != name) continue;
    bool all = true;
    for (const std::string& label : labels) all = all && series.find(label) != std::string::npos;
    if (all) total += std::stod(line.substr(line.rfind(' ') + 1));
  }
  return total;
}

json expect_problem(const httplib::Result& res, int status) {
  EXPECT_TRUE(res) << httplib::to_string(res.error());
  if (!res) return json();
  EXPECT_EQ(res->status, status) << res->body;
  EXPECT_EQ(res->get_header_value("Content-Type"), "application/problem+json");
  json problem = json::parse(res->body, nullptr, false);
  EXPECT_TRUE(problem.is_object()) << res->body;
  if (!problem.is_object()) return json();
  EXPECT_EQ(problem.value("status", 0), status);
  EXPECT_EQ(problem.value("type", ""), "about:blank");
  EXPECT_TRUE(problem.contains("title") && problem.contains("detail"));
  // type about:blank: the title is the reason phrase the status line carries (RFC 9457 4.2.1).
  EXPECT_EQ(problem.value("title", ""), res->reason) << res->body;
  return problem;
}

void expect_problem_with(const httplib::Result& res, int status, const std::string& header, const std::string& value) {
  expect_problem(res, status);
  ASSERT_TRUE(res);
  EXPECT_EQ(res->get_header_value(header), value) << header;
}

void expect_healthy(const TestServer& server) {
  auto res = server.client().Get("/livez");
  ASSERT_TRUE(res) << httplib::to_string(res.error());
  EXPECT_EQ(res->status, 200);
  EXPECT_EQ(json::parse(res->body), json({{"status", "ok"}}));
}

PngSize png_size(const std::string& png) {
  static const std::string signature = "\x89PNG\r\n\x1a\n";
  EXPECT_GE(png.size(), 24u);
  if (png.size() < 24) return {};
  EXPECT_EQ(png.substr(0, 8), signature);
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  auto be32 = [&](size_t at) {
    return uint32_t(uint8_t(png[at])) << 24 | uint32_t(uint8_t(png[at + 1])) << 16 |
           uint32_t(uint8_t(png[at + 2])) << 8 | uint32_t(uint8_t(png[at + 3]));
  };
  return {be32(16), be32(20)};
}

int connect_loopback(int port) {
  int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(uint16_t(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  timeval timeout{10, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

std::string raw_exchange(int port, const std::string& request) {
  int fd = connect_loopback(port);
  std::string response;
  if (fd >= 0 && ::send(fd, request.data(), request.size(), MSG_NOSIGNAL) == ssize_t(request.size())) {
    char buffer[4096];
    for (ssize_t n; (n = ::recv(fd, buffer, sizeof buffer, 0)) > 0;) response.append(buffer, size_t(n));
  }
  if (fd >= 0) ::close(fd);
  return response;
}

std::string base64_decode(const std::string& text) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
  };
  std::string out;
  uint32_t bits = 0;
  int count = 0;
  for (char c : text) {
    int v = value(c);
    if (v < 0) continue;  // '=' padding
    bits = bits << 6 | uint32_t(v);
    count += 6;
    if (count >= 8) {
      count -= 8;
      out += char((bits >> count) & 0xff);
    }
  }
  return out;
}

nlohmann::json scene_with_box_at(double x) {
  nlohmann::json scene = nlohmann::json::parse(small_request)["scene"];
  scene["solids"][0]["center"] = {x, 0.0};
  return scene;
}

httplib::Result post_scene(const TestServer& server, const nlohmann::json& scene, const httplib::Headers& headers) {
  return server.client().Post("/v1/scenes", headers, scene.dump(), "application/json");
}

}  // namespace rr::testing
