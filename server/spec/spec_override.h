// A run spec's field named by a JSON path and set to a value: one axis of a parameter sweep
// (StartSweep, `mbstream sweep --grid`). Paths use RunSpec's JSON names (as in the proto or
// in lowerCamelCase), '.' between fields, [N] for a list's element and [KEY=VALUE] for the
// element of a list of objects whose KEY is VALUE:
//   rtol   output_interval_s   target.tcp_error_m   gravity.z   initial_q[2]
//   drives[joint=joint2].pd_servo.kp   drives[0].pd_servo.trajectory.sum_of_sines.offset
#pragma once

#include <string>
#include <vector>

#include "mbstream/v1/run_spec.pb.h"

namespace mbstream {

// Sets the field at `path` of `spec` to `value` (JSON text: 1e-6, "adams", true; a word that
// is not JSON is taken as a string). Fields absent from `spec` are created; a list element
// must exist. Throws InputError "<where>: <path>: <problem>; <what to do>".
void ApplySpecOverride(const std::string& path, const std::string& value, v1::RunSpec* spec,
                       const std::string& where);

// The points of a sweep: each point's values in the order of `paths`.
struct SweepPoints {
  std::vector<std::string> paths;
  std::vector<std::vector<std::string>> points;
};

// Every combination of the axes' values (the first axis varies slowest). Throws InputError
// for an axis without values, two axes on one path, or more than `max_points` combinations.
SweepPoints GridPoints(const std::vector<std::string>& paths,
                       const std::vector<std::vector<std::string>>& values, long max_points,
                       const std::string& where);

// `base` with each point's overrides: one spec per point, in order. Throws InputError
// naming the point ("<where>: point 3 (kp=100, kd=2): <path>: ...").
// Only the points [first, first + count) when `count` >= 0.
std::vector<v1::RunSpec> ExpandSweep(const v1::RunSpec& base, const SweepPoints& sweep,
                                     const std::string& where, long first = 0, long count = -1);

}  // namespace mbstream
