// The one line that sums a run up, the same for `mbstream simulate` and `mbstream run
// --watch`: its state, frames (kept of computed), time reached, formulation, method, steps,
// CPU, and the accuracy figures it has (TCP error, energy error, loop residuals).
#pragma once

#include <cstdint>
#include <sstream>
#include <string>

#include "mbstream/v1/run.pb.h"

namespace mbstream::cli {

inline std::string SummaryLine(const std::string& state, int64_t frames, const v1::RunStats& s) {
  std::ostringstream line;
  line << state << ": " << frames;
  if (s.summary().keep() != "all" && !s.summary().keep().empty()) {
    line << " of " << s.summary().frames_computed() << " frames kept (keep " << s.summary().keep()
         << ")";
  } else {
    line << " frames";
  }
  line << " to t = " << s.t_reached_s() << " s, formulation " << s.formulation() << " ("
       << s.equations() << " equations), method " << s.method() << ", " << s.steps()
       << " steps, cpu " << s.cpu_s() * 1e3 << " ms";
  if (s.tcp_error_max_m() >= 0) line << ", TCP error " << s.tcp_error_max_m() << " m";
  if (s.energy_error_max() >= 0) line << ", energy error " << s.energy_error_max();
  if (s.loops().cut_joints_size() > 0) {
    line << ", loop residual " << s.drift_position_max_m() << " m, "
         << s.drift_orientation_max_rad() << " rad, velocity " << s.drift_velocity_max();
  }
  return line.str();
}

}  // namespace mbstream::cli
