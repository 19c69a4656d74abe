// A stored sweep's points (v1.SweepDefinition), each expanded on its own from the definition:
// a grid's point k by its index in every axis (the first axis varying slowest), a list's by
// its row. Nothing is kept per point, so a 100,000-point grid costs its axes only.
#pragma once

#include <string>
#include <vector>

#include "mbstream/v1/run_spec.pb.h"
#include "mbstream/v1/sweep.pb.h"

namespace mbstream {

class SweepPlan {
 public:
  // Most points of one sweep.
  static constexpr long kMaxPoints = 100'000;

  // Checks the definition's shape: a grid or a list, not both; no axis without values nor a
  // path swept twice; a list's rows with a value per path; at most kMaxPoints points.
  // Throws InputError naming what to change.
  explicit SweepPlan(v1::SweepDefinition definition);

  long size() const { return size_; }
  const std::vector<std::string>& paths() const { return paths_; }
  const v1::SweepDefinition& definition() const { return definition_; }
  // Point k's values, in the order of paths() (0 <= k < size()).
  std::vector<std::string> Values(long k) const;
  // The base spec with point k's values. Throws InputError "<where>: point k (path=value,
  // ...): <path>: <problem>" (ApplySpecOverride).
  v1::RunSpec Spec(long k, const std::string& where) const;
  // "path=value, ..." of point k (values shortened to 40 characters), for messages.
  std::string Label(long k) const;

 private:
  v1::SweepDefinition definition_;
  std::vector<std::string> paths_;
  long size_ = 0;
};

}  // namespace mbstream
