// The Prometheus text of the request metrics (server/metrics.hpp): a histogram is cumulative, with
// its sum and count, on durations whose sum prints exactly.
#include "server/metrics.hpp"

#include <gtest/gtest.h>

#include <string>

namespace {

using namespace rr::server;

TEST(Metrics, HistogramIsCumulativeWithSumAndCount) {
  Metrics metrics;
  // Binary fractions, so the sum prints exactly.
  metrics.record_request("/v1/render", "POST", 200, 0.00390625);
  metrics.record_request("/v1/render", "POST", 200, 0.25);
  metrics.record_request("/v1/render", "POST", 422, 20.0);
  std::string text = metrics.prometheus_text({});
  EXPECT_NE(text.find("roomrender_http_requests_total{route=\"/v1/render\",method=\"POST\",status=\"200\"} 2\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("roomrender_http_request_duration_seconds_bucket{route=\"/v1/render\",le=\"0.0025\"} 0\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("roomrender_http_request_duration_seconds_bucket{route=\"/v1/render\",le=\"0.005\"} 1\n"),
            std::string::npos);
  EXPECT_NE(text.find("roomrender_http_request_duration_seconds_bucket{route=\"/v1/render\",le=\"10\"} 2\n"),
            std::string::npos);
  EXPECT_NE(text.find("roomrender_http_request_duration_seconds_bucket{route=\"/v1/render\",le=\"+Inf\"} 3\n"),
            std::string::npos);
  EXPECT_NE(text.find("roomrender_http_request_duration_seconds_count{route=\"/v1/render\"} 3\n"), std::string::npos);
  EXPECT_NE(text.find("roomrender_http_request_duration_seconds_sum{route=\"/v1/render\"} 20.25390625\n"),
            std::string::npos);
}

}  // namespace
