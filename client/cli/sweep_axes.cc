#include "client/cli/sweep_axes.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include "server/results/results_csv.h"
#include "shared/common/check.h"

namespace mbstream::cli {

namespace {

std::vector<std::string> Split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, separator);) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

bool ToDouble(const std::string& text, double* value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), *value);
  return error == std::errc() && end == text.data() + text.size() && std::isfinite(*value);
}

constexpr long kMaxAxisValues = 100'000;

}  // namespace

v1::SweepAxis ParseGridAxis(const std::string& option) {
  const std::string usage =
      "; write PATH=START:STOP:COUNT (evenly spaced, :log for geometric) or PATH=V1,V2,..., "
      "e.g. --grid 'drives[joint=joint2].pd_servo.kp=100:1000:10'";
  const size_t eq = option.rfind('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == option.size()) {
    throw InputError("--grid " + option + ": no PATH=VALUES" + usage);
  }
  v1::SweepAxis axis;
  axis.set_path(option.substr(0, eq));
  const std::string values = option.substr(eq + 1);
  const std::vector<std::string> range = Split(values, ':');
  if (range.size() == 3 || (range.size() == 4 && range[3] == "log")) {
    double start = 0.0, stop = 0.0, count = 0.0;
    if (!ToDouble(range[0], &start) || !ToDouble(range[1], &stop) || !ToDouble(range[2], &count) ||
        count < 1 || count != std::floor(count) || count > kMaxAxisValues) {
      throw InputError("--grid " + option + ": START and STOP must be numbers and COUNT a " +
                       "whole number from 1 to " + std::to_string(kMaxAxisValues) + usage);
    }
    const bool log = range.size() == 4;
    if (log && !(start > 0.0 && stop > 0.0)) {
      throw InputError("--grid " + option + ": a :log range needs START and STOP > 0" + usage);
    }
    const long n = static_cast<long>(count);
    for (long k = 0; k < n; ++k) {
      const double f = n == 1 ? 0.0 : static_cast<double>(k) / static_cast<double>(n - 1);
      const double x = k == n - 1 ? stop
                       : log      ? start * std::pow(stop / start, f)
                                  : start + (stop - start) * f;
      axis.add_values(results_csv::Number(x));
    }
    return axis;
  }
  for (const std::string& value : Split(values, ',')) {
    if (value.empty()) throw InputError("--grid " + option + ": an empty value" + usage);
    axis.add_values(value);
  }
  return axis;
}

void ReadSweepList(const std::string& path, v1::StartSweepRequest* request) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot be read; give a CSV file of sweep points");
  std::string line;
  if (!std::getline(in, line) || line.empty()) {
    throw InputError(path + ":1: no header; give the swept paths, comma-separated");
  }
  for (const std::string& name : Split(line, ',')) request->add_list_paths(name);
  for (int number = 2; std::getline(in, line); ++number) {
    if (line.empty()) continue;
    const std::vector<std::string> values = Split(line, ',');
    if (static_cast<int>(values.size()) != request->list_paths_size()) {
      throw InputError(path + ":" + std::to_string(number) + ": " + std::to_string(values.size()) +
                       " values for " + std::to_string(request->list_paths_size()) +
                       " paths; give one value per column of the header (no quoted commas)");
    }
    v1::SweepPoint& point = *request->add_list();
    for (const std::string& value : values) point.add_values(value);
  }
  if (request->list_size() == 0) throw InputError(path + ": no points after the header");
}

}  // namespace mbstream::cli
