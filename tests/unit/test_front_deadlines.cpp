// The connection front's body deadline: the time beyond body_timeout is the lesser of the declared
// length at min_transfer_rate (the total) and the bytes received at min_body_rate, recomputed as
// bytes arrive. A body is late when the deadline its bytes so far earned passes before more arrive.
#include "server/front_deadlines.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <optional>

namespace rr::server {
namespace {

using namespace std::chrono_literals;
using std::chrono::milliseconds;

// A body of `declared` bytes arriving `chunk` bytes every `every`, the first chunk `every` after the
// head: when it gets 408 (counted from the head), or nullopt when it arrives whole in time.
std::optional<milliseconds> late_after(const DeadlinePolicy& policy, uint64_t declared, uint64_t chunk,
                                       milliseconds every) {
  const FrontClock::time_point start{};
  uint64_t received = 0;
  FrontClock::time_point deadline = body_deadline(policy, start, declared, received);
  for (FrontClock::time_point now = start + every; received < declared; now += every) {
    if (now > deadline) return std::chrono::duration_cast<milliseconds>(deadline - start);
    received = std::min(declared, received + chunk);
    deadline = body_deadline(policy, start, declared, received);
  }
  return std::nullopt;
}

TEST(FrontDeadlines, BodyAtOneBytePerSecondIsLateAtItsTimeoutWhateverItDeclares) {
  const DeadlinePolicy policy;  // 20 s, 256 KiB/s, 500 B/s: the service's defaults
  for (uint64_t declared : {uint64_t(100), uint64_t(1) << 20, uint64_t(64) << 20}) {
    std::optional<milliseconds> late = late_after(policy, declared, 1, 1s);
    ASSERT_TRUE(late) << declared;
    EXPECT_GE(*late, 20s) << declared;
    EXPECT_LT(*late, 21s) << declared;
  }
}

TEST(FrontDeadlines, WithoutAMinimumRateTheDeclaredLengthBuysItsTotal) {
  DeadlinePolicy policy;
  policy.min_body_rate = 0;
  std::optional<milliseconds> late = late_after(policy, 1u << 20, 1, 1s);
  ASSERT_TRUE(late);
  EXPECT_EQ(*late, 24s);  // 20 s + 1 MiB at 256 KiB/s
}

TEST(FrontDeadlines, BodiesAtOrdinaryRatesArriveInTime) {
  const DeadlinePolicy policy;
  EXPECT_FALSE(late_after(policy, 50u << 20, 1u << 20, 1s)) << "50 MiB at 1 MiB/s";
  EXPECT_FALSE(late_after(policy, 50u << 20, 64u << 10, 100ms)) << "50 MiB at 640 KiB/s";
}

TEST(FrontDeadlines, BytesReceivedEarnTimeUpToTheDeclaredTotal) {
  const DeadlinePolicy policy;
  const FrontClock::time_point start{};
  // 2 MiB declared: the total is 20 s + 8 s.
  EXPECT_EQ(body_deadline(policy, start, 2u << 20, 0), start + 20s);
  EXPECT_EQ(body_deadline(policy, start, 2u << 20, 2000), start + 24s);
  EXPECT_EQ(body_deadline(policy, start, 2u << 20, 1u << 20), start + 28s);
  EXPECT_EQ(body_deadline(policy, start, 2u << 20, 4u << 20), start + 28s);
}

}  // namespace
}  // namespace rr::server
