// The transport seam over real sockets. Screening decides from the head alone: a request it refuses
// is answered before any of its body is read, and "100 Continue" comes only once the head passed
// (a 415 for a wrong Content-Type and a 401 for a missing token, each with Expect and a 4 MiB body
// declared and never sent); a body trickled at 1 byte/s gets 408 by its timeout, while a 50 MiB
// import at full speed is answered. Every read has a deadline, so nothing here can hang.
#include "server_fixture.hpp"

#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <string_view>
#include <thread>

namespace {

using nlohmann::json;
using namespace rr::testing;
using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

constexpr size_t four_mib = 4u << 20;

// One client connection driven by hand: it sends what the test says and reads what arrives.
class RawClient {
 public:
  explicit RawClient(int port) : fd_(connect_loopback(port)) {}
  ~RawClient() {
    if (fd_ >= 0) ::close(fd_);
  }
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;

  bool ok() const { return fd_ >= 0; }
  bool send(std::string_view bytes) {
    while (!bytes.empty()) {
      ssize_t n = ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
      if (n <= 0) return false;
      bytes.remove_prefix(size_t(n));
    }
    return true;
  }
  // Reads until `received()` holds `text`, the server closes, or `deadline` passes.
  bool read_until(std::string_view text, Clock::time_point deadline) {
    while (received_.find(text) == std::string::npos && !closed_) {
      auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
      if (left <= 0) return false;
      pollfd p{fd_, POLLIN, 0};
      if (::poll(&p, 1, int(left)) <= 0) continue;
      char buffer[16384];
      ssize_t n = ::recv(fd_, buffer, sizeof buffer, MSG_DONTWAIT);
      if (n > 0) {
        received_.append(buffer, size_t(n));
      } else if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
        closed_ = true;
      }
    }
    return received_.find(text) != std::string::npos;
  }
  // Reads until the server closes the connection or `deadline` passes; true when it closed.
  bool read_until_closed(Clock::time_point deadline) {
    read_until(std::string(1, '\0') + "never", deadline);
    return closed_;
  }
  const std::string& received() const { return received_; }

 private:
  int fd_ = -1;
  std::string received_;
  bool closed_ = false;
};

std::string head_with_declared_body(const std::string& path, const std::string& headers, size_t length) {
  return "POST " + path + " HTTP/1.1\r\nHost: test\r\n" + headers + "Content-Length: " + std::to_string(length) +
         "\r\n\r\n";
}

// The answer a client gets to a head with Expect whose body it never sends: `status`, problem+json,
// no "100 Continue" before it, and the connection closed after it.
std::string expect_refused_before_the_body(int port, const std::string& head, int status) {
  RawClient client(port);
  EXPECT_TRUE(client.ok());
  EXPECT_TRUE(client.send(head));
  auto start = Clock::now();
  EXPECT_TRUE(client.read_until_closed(start + 5s)) << "the connection stayed open: " << client.received();
  const std::string& answer = client.received();
  EXPECT_TRUE(answer.starts_with("HTTP/1.1 " + std::to_string(status) + " ")) << answer.substr(0, 300);
  EXPECT_EQ(answer.find("100 Continue"), std::string::npos) << answer.substr(0, 300);
  EXPECT_NE(answer.find("Content-Type: application/problem+json"), std::string::npos) << answer.substr(0, 300);
  EXPECT_NE(answer.find("Connection: close"), std::string::npos) << answer.substr(0, 300);
  EXPECT_LT(std::chrono::duration<double>(Clock::now() - start).count(), 2.0) << "the refusal waited for the body";
  return answer;
}

class TransportTest : public SharedServerTest<TransportTest> {};

TEST_F(TransportTest, WrongContentTypeWithExpectIs415BeforeTheBody) {
  expect_refused_before_the_body(
      server_->port(),
      head_with_declared_body("/v1/render", "Content-Type: text/plain\r\nExpect: 100-continue\r\n", four_mib), 415);
  expect_healthy(*server_);
}

TEST_F(TransportTest, MissingTokenWithExpectIs401BeforeTheBody) {
  rr::server::ServerConfig config = test_server_config();
  config.api_token_file = output_dir("integration") / "transport.tokens";
  write_file(config.api_token_file, "alice:alice-0123456789abcdef\n");
  TestServer server(config);
  std::string answer = expect_refused_before_the_body(
      server.port(),
      head_with_declared_body("/v1/scenes", "Content-Type: application/json\r\nExpect: 100-continue\r\n", four_mib),
      401);
  EXPECT_NE(answer.find("WWW-Authenticate: Bearer"), std::string::npos) << answer.substr(0, 300);
  // With the token the same head is let through: "100 Continue", then the body's own answer.
  RawClient client(server.port());
  ASSERT_TRUE(client.ok());
  const std::string scene = json::parse(small_request)["scene"].dump();
  ASSERT_TRUE(client.send(head_with_declared_body(
      "/v1/scenes",
      "Content-Type: application/json\r\nAuthorization: Bearer alice-0123456789abcdef\r\nExpect: 100-continue\r\n",
      scene.size())));
  ASSERT_TRUE(client.read_until("HTTP/1.1 100 Continue\r\n\r\n", Clock::now() + 5s)) << client.received();
  ASSERT_TRUE(client.send(scene));
  ASSERT_TRUE(client.read_until("\r\n\r\n{", Clock::now() + 10s)) << client.received();
  EXPECT_NE(client.received().find("HTTP/1.1 201 Created"), std::string::npos) << client.received().substr(0, 300);
}

// Without Expect the client sends its body at once; a refusal still comes from the head, before the
// server has read the body, and the connection closes instead of taking the rest.
TEST_F(TransportTest, RefusalWithoutExpectComesBeforeTheBodyIsRead) {
  RawClient client(server_->port());
  ASSERT_TRUE(client.ok());
  ASSERT_TRUE(client.send(head_with_declared_body("/v1/render", "Content-Type: text/plain\r\n", four_mib)));
  ASSERT_TRUE(client.send(std::string(64 * 1024, ' ')));
  ASSERT_TRUE(client.read_until("\r\n\r\n", Clock::now() + 5s)) << client.received();
  EXPECT_TRUE(client.received().starts_with("HTTP/1.1 415 ")) << client.received().substr(0, 300);
  EXPECT_TRUE(client.read_until_closed(Clock::now() + 5s));
  expect_healthy(*server_);
}

TEST_F(TransportTest, AcceptedHeadWithExpectGets100ContinueThenItsAnswer) {
  RawClient client(server_->port());
  ASSERT_TRUE(client.ok());
  const std::string body = small_request;
  ASSERT_TRUE(client.send(head_with_declared_body(
      "/v1/render", "Content-Type: application/json\r\nExpect: 100-continue\r\n", body.size())));
  ASSERT_TRUE(client.read_until("HTTP/1.1 100 Continue\r\n\r\n", Clock::now() + 5s)) << client.received();
  EXPECT_TRUE(client.received().starts_with("HTTP/1.1 100 Continue\r\n\r\n")) << client.received();
  ASSERT_TRUE(client.send(body));
  ASSERT_TRUE(client.read_until("image/png", Clock::now() + 10s)) << client.received().substr(0, 300);
  EXPECT_NE(client.received().find("HTTP/1.1 200 OK"), std::string::npos) << client.received().substr(0, 300);
}

// A body trickled at 1 byte/s earns 2 ms a byte (1 s per 500 bytes), so it gets 408 about 20 s after
// its head, under the service's default deadlines; the declared 1 MiB would buy 24 s were the
// deadline a total alone.
TEST_F(TransportTest, BodyAtOneBytePerSecondGets408Within21Seconds) {
  rr::server::ServerConfig config = test_server_config();
  config.body_timeout_ms = 20'000;
  config.min_transfer_rate = 256u << 10;
  config.min_body_rate = 500;
  TestServer server(config);
  RawClient client(server.port());
  ASSERT_TRUE(client.ok());
  ASSERT_TRUE(client.send(head_with_declared_body("/v1/render", "Content-Type: application/json\r\n", 1u << 20)));
  const auto start = Clock::now();
  bool answered = false;
  for (int second = 1; second <= 23 && !answered; ++second) {
    client.send("{");  // fails once the server closed; the answer is read below
    answered = client.read_until("\r\n\r\n", start + std::chrono::seconds(second));
  }
  const double after = std::chrono::duration<double>(Clock::now() - start).count();
  ASSERT_TRUE(answered) << "no answer within 23 s";
  EXPECT_TRUE(client.received().starts_with("HTTP/1.1 408 ")) << client.received().substr(0, 300);
  EXPECT_NE(client.received().find("Connection: close"), std::string::npos) << client.received().substr(0, 300);
  EXPECT_GE(after, 19.5) << "408 before the body's timeout";
  EXPECT_LT(after, 21.0) << "the trickle kept the connection";
  EXPECT_TRUE(client.read_until_closed(Clock::now() + 3s));
  std::printf("1 byte/s body answered 408 after %.2f s\n", after);
}

// 50 MiB (the limit is 64 MiB) at loopback speed: received whole and answered, the minimum rate no
// obstacle. The file is a triangle and comment lines, so the import itself is quick.
TEST_F(TransportTest, FiftyMebibyteImportAtFullSpeedIsAnswered) {
  std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
  const std::string comment = "# " + std::string(97, 'c') + "\n";
  obj.reserve(50u << 20);
  while (obj.size() + comment.size() <= (50u << 20)) obj += comment;
  obj.append((50u << 20) - obj.size(), '\n');
  ASSERT_EQ(obj.size(), 50u << 20);
  auto start = Clock::now();
  auto res = server_->client(120).Post("/v1/import/obj", obj, "model/obj");
  ASSERT_TRUE(res) << httplib::to_string(res.error());
  EXPECT_EQ(res->status, 200) << res->body.substr(0, 300);
  EXPECT_TRUE(json::parse(res->body).contains("scene")) << res->body.substr(0, 300);
  std::printf("50 MiB import answered %d after %.2f s\n", res->status,
              std::chrono::duration<double>(Clock::now() - start).count());
}

}  // namespace
