#include "server/runs/sweep_plan.h"

#include <set>

#include "server/spec/spec_override.h"
#include "shared/common/check.h"

namespace mbstream {

SweepPlan::SweepPlan(v1::SweepDefinition definition) : definition_(std::move(definition)) {
  const v1::SweepDefinition& d = definition_;
  if (d.grid_size() > 0 && (d.list_size() > 0 || d.list_paths_size() > 0)) {
    throw InputError("StartSweep: give a grid or a list, not both");
  }
  if (d.grid_size() > 0) {
    std::set<std::string> seen;
    size_ = 1;
    for (const v1::SweepDefinition::Axis& axis : d.grid()) {
      if (!seen.insert(axis.path()).second) {
        throw InputError("grid: " + axis.path() + " is swept twice; give each path once");
      }
      if (axis.values_size() == 0) {
        throw InputError("grid: " + axis.path() + " has no values; give at least one");
      }
      size_ *= axis.values_size();
      if (size_ > kMaxPoints) {
        throw InputError("grid: the grid has more than " + std::to_string(kMaxPoints) +
                         " points; sweep fewer values, or split the sweep");
      }
      paths_.push_back(axis.path());
    }
    return;
  }
  if (d.list_size() == 0) {
    throw InputError("StartSweep: the sweep has no points; give grid axes or list points");
  }
  if (d.list_size() > kMaxPoints) {
    throw InputError("list: more than " + std::to_string(kMaxPoints) + " points; split the sweep");
  }
  paths_.assign(d.list_paths().begin(), d.list_paths().end());
  for (int k = 0; k < d.list_size(); ++k) {
    if (d.list(k).values_size() != static_cast<int>(paths_.size())) {
      throw InputError("sweep: point " + std::to_string(k) + " has " +
                       std::to_string(d.list(k).values_size()) + " values for " +
                       std::to_string(paths_.size()) + " paths; give one value per path");
    }
  }
  size_ = d.list_size();
}

std::vector<std::string> SweepPlan::Values(long k) const {
  MBSTREAM_CHECK(k >= 0 && k < size_);
  const v1::SweepDefinition& d = definition_;
  if (d.grid_size() == 0) {
    const auto& values = d.list(static_cast<int>(k)).values();
    return {values.begin(), values.end()};
  }
  std::vector<std::string> values(paths_.size());
  long rest = k;
  for (int a = d.grid_size(); a-- > 0;) {  // the last axis varies fastest
    const auto& axis = d.grid(a);
    values[static_cast<size_t>(a)] = axis.values(static_cast<int>(rest % axis.values_size()));
    rest /= axis.values_size();
  }
  return values;
}

std::string SweepPlan::Label(long k) const {
  const std::vector<std::string> values = Values(k);
  std::string label;
  for (size_t a = 0; a < values.size(); ++a) {
    label += (a ? ", " : "") + paths_[a] + "=" + values[a].substr(0, 40);
  }
  return label;
}

v1::RunSpec SweepPlan::Spec(long k, const std::string& where) const {
  const std::vector<std::string> values = Values(k);
  v1::RunSpec spec = definition_.base();
  const std::string at = where + ": point " + std::to_string(k) + " (" + Label(k) + ")";
  for (size_t a = 0; a < values.size(); ++a) ApplySpecOverride(paths_[a], values[a], &spec, at);
  return spec;
}

}  // namespace mbstream
