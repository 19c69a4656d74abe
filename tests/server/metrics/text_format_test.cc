// The Prometheus text format: escaping, values, names, and a registry's exposition with
// histogram buckets, _sum and _count.
#include <gmock/gmock.h>

#include <cmath>
#include <limits>

#include "server/metrics/metric_registry.h"
#include "server/metrics/text_format.h"

namespace mbstream::metrics {
namespace {

using ::testing::HasSubstr;

TEST(TextFormatTest, EscapesLabelValuesAndHelp) {
  EXPECT_EQ(EscapeLabelValue(R"(a\b"c)"
                             "\n"
                             "d"),
            R"(a\\b\"c\nd)");
  EXPECT_EQ(EscapeHelp(R"(a\b"c)"
                       "\n"),
            R"(a\\b"c\n)");  // quotes stay in HELP
  TextWriter out;
  out.Family("x_total", "line one\nline two", "counter");
  out.Sample("x_total", {{"path", "C:\\runs\\\"a\""}}, 2);
  EXPECT_EQ(out.text(),
            "# HELP x_total line one\\nline two\n"
            "# TYPE x_total counter\n"
            "x_total{path=\"C:\\\\runs\\\\\\\"a\\\"\"} 2\n");
}

TEST(TextFormatTest, FormatsValuesAsPrometheusReadsThem) {
  EXPECT_EQ(FormatValue(3), "3");
  EXPECT_EQ(FormatValue(0.25), "0.25");
  EXPECT_EQ(FormatValue(0.1), "0.1");
  EXPECT_EQ(FormatValue(1e-5), "1e-05");
  EXPECT_EQ(FormatValue(0.0008), "0.0008");
  EXPECT_EQ(FormatValue(-2), "-2");
  EXPECT_EQ(FormatValue(std::numeric_limits<double>::infinity()), "+Inf");
  EXPECT_EQ(FormatValue(-std::numeric_limits<double>::infinity()), "-Inf");
  EXPECT_EQ(FormatValue(std::nan("")), "NaN");
}

TEST(TextFormatTest, MetricNamesAreChecked) {
  EXPECT_TRUE(IsMetricName("mbstream_frames_total"));
  EXPECT_TRUE(IsMetricName("job:rate5m"));
  EXPECT_FALSE(IsMetricName("1abc"));
  EXPECT_FALSE(IsMetricName("a-b"));
  EXPECT_FALSE(IsMetricName(""));
  EXPECT_TRUE(IsLabelName("state"));
  EXPECT_FALSE(IsLabelName("__name"));
  EXPECT_FALSE(IsLabelName("a:b"));
  Registry registry;
  EXPECT_THROW(registry.Counters("bad-name", "h"), std::invalid_argument);
  EXPECT_THROW(registry.Counters("ok_total", "h", {"le"}), std::invalid_argument);
  registry.Counters("ok_total", "h");
  EXPECT_THROW(registry.Gauges("ok_total", "h"), std::invalid_argument);
  EXPECT_THROW(registry.Histograms("h_seconds", "h", {1.0, 0.5}), std::invalid_argument);
  EXPECT_THROW(registry.Counters("l_total", "h", {"a"}).With({}), std::invalid_argument);
}

TEST(TextFormatTest, HistogramBucketsAreCumulativeWithSumAndCount) {
  Registry registry;
  Histogram& latency =
      registry.Histograms("op_seconds", "Time of an op", {0.25, 1, 4}, {"op"}).With({"get"});
  // Binary fractions: the sum is exact.
  for (const double value : {0.125, 0.25, 0.5, 2.0, 8.0, 16.0}) latency.Observe(value);
  latency.Observe(std::nan(""));  // not counted
  EXPECT_EQ(latency.count(), 6u);
  EXPECT_EQ(registry.Exposition(),
            "# HELP op_seconds Time of an op\n"
            "# TYPE op_seconds histogram\n"
            "op_seconds_bucket{op=\"get\",le=\"0.25\"} 2\n"
            "op_seconds_bucket{op=\"get\",le=\"1\"} 3\n"
            "op_seconds_bucket{op=\"get\",le=\"4\"} 4\n"
            "op_seconds_bucket{op=\"get\",le=\"+Inf\"} 6\n"
            "op_seconds_sum{op=\"get\"} 26.875\n"
            "op_seconds_count{op=\"get\"} 6\n");
}

TEST(TextFormatTest, RegistryWritesFamiliesInOrder) {
  Registry registry;
  Family<Counter>& ended = registry.Counters("runs_ended_total", "Runs ended", {"state"});
  ended.With({"finished"}).Add(3);
  ended.With({"failed"}).Add();
  EXPECT_EQ(&ended.With({"finished"}), &ended.With({"finished"}));
  registry.Gauges("queued", "Queued").With({}).Set(2);
  registry.GaugeFunction("subscribers", "Streams", [] { return 7.0; });
  EXPECT_EQ(registry.Exposition(),
            "# HELP runs_ended_total Runs ended\n"
            "# TYPE runs_ended_total counter\n"
            "runs_ended_total{state=\"finished\"} 3\n"
            "runs_ended_total{state=\"failed\"} 1\n"
            "# HELP queued Queued\n"
            "# TYPE queued gauge\n"
            "queued 2\n"
            "# HELP subscribers Streams\n"
            "# TYPE subscribers gauge\n"
            "subscribers 7\n");
  EXPECT_EQ(ExponentialBuckets(0.5, 2, 3), (std::vector<double>{0.5, 1, 2}));
}

}  // namespace
}  // namespace mbstream::metrics
