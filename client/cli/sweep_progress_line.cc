#include "client/cli/sweep_progress_line.h"

#include <sstream>

#include "server/wire/stats_conversion.h"

namespace mbstream::cli {

std::string SweepProgressLine(const v1::SweepProgress& progress) {
  std::ostringstream line;
  line << "sweep " << progress.sweep_id() << ": " << progress.ended_runs() << "/"
       << progress.total_points() << " runs ended";
  std::string ended, pending;
  for (const v1::SweepStateCount& entry : progress.states()) {
    if (IsFinalState(entry.state())) {
      ended += (ended.empty() ? "" : ", ") + v1::RunState_Name(entry.state()) + " " +
               std::to_string(entry.runs());
    } else {
      std::string name = v1::RunState_Name(entry.state());
      for (char& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      pending += ", " + std::to_string(entry.runs()) + " " + name;
    }
  }
  if (!ended.empty()) line << " (" << ended << ")";
  line << pending;
  if (const int left = progress.total_points() - progress.started_runs(); left > 0) {
    line << ", " << left << " not started";
  }
  if (progress.cancelled()) line << " - cancelled";
  return line.str();
}

}  // namespace mbstream::cli
