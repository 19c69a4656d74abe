#include "client/cli/progress_line.h"

#include <cstdio>

namespace mbstream::cli {

std::string ProgressLine(const v1::RunInfo& info, double elapsed_s) {
  const double duration = info.duration_s();
  const double t = info.t_s();
  const double percent = duration > 0 ? 100.0 * t / duration : 0.0;
  char line[256];
  int used = std::snprintf(line, sizeof(line), "%s %s t = %.3f/%.3f s %5.1f%%", info.id().c_str(),
                           v1::RunState_Name(info.state()).c_str(), t, duration, percent);
  if (info.state() == v1::RUNNING && elapsed_s > 0 && t > 0) {
    const double rate = t / elapsed_s;  // simulated seconds per wall second
    std::snprintf(line + used, sizeof(line) - used, "  %.3gx real time  ETA %.1f s", rate,
                  (duration - t) / rate);
  }
  std::string text = line;
  if (!info.controller().empty()) text += "  controlled by " + info.controller();
  return text;
}

}  // namespace mbstream::cli
