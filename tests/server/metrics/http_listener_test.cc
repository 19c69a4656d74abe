// The metrics HTTP listener over loopback: GET /metrics, 404, 405, port 0, a bad address;
// and the hot-path metric updates allocate nothing.
#include <gmock/gmock.h>

#include "server/metrics/http_listener.h"
#include "server/metrics/metric_registry.h"
#include "tests/common/allocation_counter.h"
#include "tests/common/http_get.h"

namespace mbstream::metrics {
namespace {

using ::testing::HasSubstr;
using ::testing::StartsWith;

std::string Exchange(int port, const std::string& request) {
  const std::string answer = mbstream::testing::HttpExchange(port, request);
  return answer.empty() ? "connect failed" : answer;
}

int PortOf(const std::string& address) { return std::stoi(address.substr(address.rfind(':') + 1)); }

TEST(HttpListenerTest, ServesTheExpositionAtMetrics) {
  Registry registry;
  registry.Counters("mbstream_frames_total", "Frames").With({}).Add(41);
  auto listener = HttpListener::Start("127.0.0.1:0", [&registry] { return registry.Exposition(); });
  EXPECT_THAT(listener->address(), StartsWith("127.0.0.1:"));
  const int port = PortOf(listener->address());
  ASSERT_GT(port, 0);
  const std::string ok = Exchange(port, "GET /metrics HTTP/1.1\r\nHost: x\r\n\r\n");
  EXPECT_THAT(ok, StartsWith("HTTP/1.1 200 OK\r\n"));
  EXPECT_THAT(ok, HasSubstr("Content-Type: text/plain; version=0.0.4"));
  EXPECT_THAT(ok, HasSubstr("\r\n\r\n# HELP mbstream_frames_total Frames\n"));
  EXPECT_THAT(ok, HasSubstr("\nmbstream_frames_total 41\n"));
  // The counter moves between scrapes.
  registry.Counters("other_total", "Other").With({}).Add();
  EXPECT_THAT(Exchange(port, "GET /metrics?x=1 HTTP/1.0\r\n\r\n"), HasSubstr("other_total 1\n"));
  EXPECT_THAT(Exchange(port, "GET / HTTP/1.1\r\n\r\n"), StartsWith("HTTP/1.1 404"));
  const std::string post = Exchange(port, "POST /metrics HTTP/1.1\r\n\r\n");
  EXPECT_THAT(post, StartsWith("HTTP/1.1 405"));
  EXPECT_THAT(post, HasSubstr("Allow: GET"));
  EXPECT_THAT(Exchange(port, "garbage"), StartsWith("HTTP/1.1 400"));  // ended half-way
}

TEST(HttpListenerTest, RefusesAnAddressItCannotUseWithAMessage) {
  auto first = HttpListener::Start("127.0.0.1:0", [] { return ""; });
  try {
    HttpListener::Start(first->address(), [] { return ""; });
    FAIL() << "a port in use was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_THAT(error.what(), HasSubstr("cannot serve metrics on " + first->address()));
    EXPECT_THAT(error.what(), HasSubstr("in use"));
  }
  EXPECT_THROW(HttpListener::Start("no-port", [] { return ""; }), std::runtime_error);
}

TEST(MetricRegistryTest, UpdatesAllocateNothing) {
  Registry registry;
  Counter& frames = registry.Counters("f_total", "f").With({});
  Gauge& queued = registry.Gauges("q", "q").With({});
  Histogram& latency =
      registry.Histograms("l_seconds", "l", ExponentialBuckets(1e-4, 2, 15)).With({});
  const long before = mbstream::testing::AllocationCount();
  for (int i = 0; i < 1000; ++i) {
    frames.Add();
    queued.Set(i);
    latency.Observe(i * 1e-4);
  }
  EXPECT_EQ(mbstream::testing::AllocationCount(), before);
  EXPECT_EQ(frames.value(), 1000);
  EXPECT_EQ(latency.count(), 1000u);
}

}  // namespace
}  // namespace mbstream::metrics
