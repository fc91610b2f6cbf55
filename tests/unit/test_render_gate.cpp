// The render gate (server/render_gate.hpp): admission up to the concurrency, a bounded queue served in
// arrival order, queued work that expires at its deadline, and abort cancelling running work; the
// render threads (server/render_workers.hpp) that admitted renders run on.
#include "server/render_gate.hpp"
#include "server/render_workers.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

namespace {

using namespace rr::server;
using namespace std::chrono_literals;

// A token whose deadline is `budget` from now (tokens hold an atomic, so they are built in place).
struct Token : rr::CancelToken {
  explicit Token(std::chrono::milliseconds budget) { deadline = std::chrono::steady_clock::now() + budget; }
};

TEST(RenderGate, AdmitsUpToConcurrencyQueuesUpToTheLimitAndRefusesBeyond) {
  RenderGate gate(1, 1);
  Token first(5s);
  ASSERT_EQ(gate.enter(first), RenderGate::Admission::admitted);
  Token second(5s);
  auto waiting = std::async(std::launch::async, [&] { return gate.enter(second); });
  while (gate.load().queued == 0) std::this_thread::sleep_for(1ms);
  Token third(5s);
  EXPECT_EQ(gate.enter(third), RenderGate::Admission::saturated);
  EXPECT_TRUE(gate.load().saturated());
  gate.leave(first);
  EXPECT_EQ(waiting.get(), RenderGate::Admission::admitted);
  EXPECT_EQ(gate.load().running, 1u);
  gate.leave(second);
  EXPECT_EQ(gate.load().running, 0u);
}

TEST(RenderGate, AdmitsInArrivalOrder) {
  RenderGate gate(1, 8);
  Token holder(5s);
  ASSERT_EQ(gate.enter(holder), RenderGate::Admission::admitted);
  std::vector<rr::CancelToken> tokens(4);
  std::vector<int> order;
  std::mutex order_mutex;
  std::vector<std::thread> waiters;
  for (int i = 0; i < 4; ++i) {
    tokens[size_t(i)].deadline = std::chrono::steady_clock::now() + 5s;
    waiters.emplace_back([&, i] {
      EXPECT_EQ(gate.enter(tokens[size_t(i)]), RenderGate::Admission::admitted);
      {
        std::lock_guard lock(order_mutex);
        order.push_back(i);
      }
      gate.leave(tokens[size_t(i)]);
    });
    while (gate.load().queued != size_t(i) + 1) std::this_thread::sleep_for(1ms);  // arrive one by one
  }
  gate.leave(holder);
  for (std::thread& t : waiters) t.join();
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3}));
}

TEST(RenderGate, QueuedWorkExpiresAtItsDeadlineAndAbortCancelsRunningWork) {
  RenderGate gate(1, 1);
  Token running(5s);
  ASSERT_EQ(gate.enter(running), RenderGate::Admission::admitted);
  Token late(30ms);
  EXPECT_EQ(gate.enter(late), RenderGate::Admission::expired);
  EXPECT_EQ(gate.load().queued, 0u);
  gate.close();
  Token after_close(5s);
  EXPECT_EQ(gate.enter(after_close), RenderGate::Admission::closed);
  EXPECT_FALSE(gate.wait_idle(std::chrono::steady_clock::now() + 10ms));
  gate.abort();
  EXPECT_TRUE(running.expired()) << "abort cancels what runs";
  gate.leave(running);
  EXPECT_TRUE(gate.wait_idle(std::chrono::steady_clock::now() + 10ms));
}

// Renders run on the render threads, not the caller's; what a job returns or throws reaches its
// caller; jobs of many callers at once all run, on no more threads than were made.
TEST(RenderWorkers, JobsRunOnTheirOwnThreadsAndAnswerTheirCallers) {
  RenderWorkers threads(2);
  EXPECT_NE(threads.run([] { return std::this_thread::get_id(); }), std::this_thread::get_id());
  EXPECT_EQ(threads.run([] { return 41 + 1; }), 42);
  EXPECT_THROW(threads.run([]() -> int { throw std::runtime_error("a render failed"); }), std::runtime_error);
  std::mutex mutex;
  std::set<std::thread::id> seen;
  std::vector<std::thread> callers;
  std::atomic<int> done{0};
  for (int i = 0; i < 8; ++i) {
    callers.emplace_back([&] {
      const std::thread::id id = threads.run([] {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        return std::this_thread::get_id();
      });
      std::lock_guard lock(mutex);
      seen.insert(id);
      ++done;
    });
  }
  for (std::thread& t : callers) t.join();
  EXPECT_EQ(done.load(), 8);
  EXPECT_GE(seen.size(), 1u);
  EXPECT_LE(seen.size(), 2u);
}

}  // namespace
