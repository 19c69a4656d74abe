// Prometheus text exposition format, version 0.0.4
// (https://prometheus.io/docs/instrumenting/exposition_formats/): one "# HELP" and "# TYPE"
// line per metric family, then one line per sample, `name{label="value",...} value`.
//
// Written here rather than taken from prometheus-cpp because Debian 12 ships no
// libprometheus-cpp-dev (no apt candidate on bookworm); the format is small and stable, and
// this writer is the only part of it we need.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mbstream::metrics {

// The Content-Type of the text format.
inline constexpr const char* kTextContentType = "text/plain; version=0.0.4; charset=utf-8";

using Labels = std::vector<std::pair<std::string, std::string>>;  // name, value

// A label value with backslash, double quote and line feed escaped (\\, \", \n).
std::string EscapeLabelValue(std::string_view value);
// A HELP text with backslash and line feed escaped (\\, \n).
std::string EscapeHelp(std::string_view help);
// A sample value: the shortest text that reads back to the same double in %g style (3, 0.25,
// 0.0008, 1e-05), +Inf, -Inf, NaN as Prometheus spells them.
std::string FormatValue(double value);

// Whether `name` is a valid metric name ([a-zA-Z_:][a-zA-Z0-9_:]*) or label name
// ([a-zA-Z_][a-zA-Z0-9_]*, not starting with "__", which Prometheus reserves).
bool IsMetricName(std::string_view name);
bool IsLabelName(std::string_view name);

// Appends the exposition to a string, family by family.
class TextWriter {
 public:
  // "# HELP name help" and "# TYPE name type" (type: counter, gauge, histogram, untyped).
  void Family(std::string_view name, std::string_view help, std::string_view type);
  // "name{labels} value"; no braces without labels.
  void Sample(std::string_view name, const Labels& labels, double value);

  const std::string& text() const { return text_; }

 private:
  std::string text_;
};

}  // namespace mbstream::metrics
