// What operators use on a real server (issue 16): --metrics on port 0 (its log names the bound
// port, a short run moves the counters, GET /metrics over loopback shows them in the
// Prometheus text format) and `mbstream health`, the readiness probe of deploy/k8s/.
#include <gmock/gmock.h>

#include <filesystem>
#include <random>
#include <regex>

#include "tests/common/http_get.h"
#include "tests/common/server_process.h"

namespace mbstream::testing {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// GET /metrics from 127.0.0.1:port; the whole answer.
std::string Scrape(int port) {
  return HttpExchange(port, "GET /metrics HTTP/1.1\r\nHost: localhost\r\n\r\n");
}

// The value of the sample line that starts with `series` ("name{labels}"), or -1.
double Sample(const std::string& text, const std::string& series) {
  const size_t at = text.find("\n" + series + " ");
  if (at == std::string::npos) return -1;
  return std::stod(text.substr(at + series.size() + 2));
}

TEST(MetricsE2eTest, ARunMovesTheCountersScrapedOverLoopback) {
  const fs::path dir = fs::temp_directory_path() /
                       ("mbstream-metrics-e2e-" + std::to_string(std::random_device()()));
  {
    ServerProcess server(MBSTREAM_SERVER, dir.string(), {"--metrics", "127.0.0.1:0"});
    const std::optional<std::string> url = WaitForLineIn(server.log_path(), "metrics on http://");
    ASSERT_TRUE(url) << ReadTextFile(server.log_path());
    std::smatch port_match;
    ASSERT_TRUE(std::regex_search(*url, port_match, std::regex(R"(^127\.0\.0\.1:(\d+)/metrics$)")))
        << *url;
    const int port = std::stoi(port_match[1]);
    ASSERT_GT(port, 0);

    const std::string before = Scrape(port);
    ASSERT_THAT(before, HasSubstr("HTTP/1.1 200 OK"));
    EXPECT_EQ(Sample(before, "mbstream_frames_total"), 0);
    EXPECT_EQ(Sample(before, R"(mbstream_runs_ended_total{state="finished"})"), 0);
    EXPECT_EQ(Sample(before, "mbstream_subscribers"), 0);

    const CommandOutcome run =
        RunCommand(std::string(MBSTREAM_CLI) + " --server " + server.address() +
                   " run single_pendulum --duration 1 --output-interval "
                   "0.01 --realtime 0 --watch");
    ASSERT_EQ(run.exit_code, 0) << run.output << ReadTextFile(server.log_path());

    const std::string after = Scrape(port);
    EXPECT_EQ(Sample(after, R"(mbstream_runs_ended_total{state="finished"})"), 1) << after;
    EXPECT_EQ(Sample(after, "mbstream_frames_total"), 101);  // t = 0, 0.01, ..., 1 s
    EXPECT_EQ(Sample(after, R"(mbstream_runs{state="queued"})"), 0);
    EXPECT_EQ(Sample(after, R"(mbstream_runs{state="running"})"), 0);
    EXPECT_GE(
        Sample(after, R"(mbstream_store_operation_duration_seconds_count{operation="put_run"})"),
        1);
    EXPECT_EQ(
        Sample(after, R"(mbstream_store_operation_duration_seconds_count{operation="finish_run"})"),
        1);
    EXPECT_THAT(after, HasSubstr("# TYPE mbstream_probe_latency_seconds histogram\n"));
    EXPECT_THAT(after, HasSubstr("mbstream_build_info{version=\""));
    EXPECT_EQ(server.Stop(), 0);
  }
  fs::remove_all(dir);
}

TEST(MetricsE2eTest, AnUnusableMetricsAddressIsRefusedAtStart) {
  const CommandOutcome bad = RunCommand(std::string(MBSTREAM_SERVER) +
                                        " --listen 127.0.0.1:0 --data /tmp/mbstream-metrics-bad "
                                        "--metrics 203.0.113.1:0");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_THAT(bad.output, HasSubstr("--metrics: cannot serve metrics on 203.0.113.1:0"));
  fs::remove_all("/tmp/mbstream-metrics-bad");
}

TEST(HealthCommandTest, SaysServingAndFailsWhenTheServerIsGone) {
  const fs::path dir =
      fs::temp_directory_path() / ("mbstream-health-e2e-" + std::to_string(std::random_device()()));
  std::string address;
  {
    ServerProcess server(MBSTREAM_SERVER, dir.string());
    address = server.address();
    const CommandOutcome health =
        RunCommand(std::string(MBSTREAM_CLI) + " --server " + address + " health");
    EXPECT_EQ(health.exit_code, 0) << health.output;
    EXPECT_EQ(health.output, "SERVING\n");
  }
  const CommandOutcome gone =
      RunCommand(std::string(MBSTREAM_CLI) + " --server " + address + " health");
  EXPECT_EQ(gone.exit_code, 3) << gone.output;  // unreachable
  EXPECT_THAT(gone.output, HasSubstr("mbstream health:"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mbstream::testing
