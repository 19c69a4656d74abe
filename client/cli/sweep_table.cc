#include "client/cli/sweep_table.h"

#include "server/results/results_csv.h"

namespace mbstream::cli {

namespace {

using results_csv::CsvField;

// A figure the run does not have (< 0) is an empty cell.
std::string Figure(double value) { return value < 0.0 ? "" : results_csv::Number(value); }

}  // namespace

std::string SweepTableHeader(const std::vector<std::string>& paths,
                             const std::vector<std::string>& joints) {
  std::string line = "run_id";
  for (const std::string& path : paths) line += "," + CsvField(path);
  line +=
      ",state,trust,t_reached_s,frames_kept,steps,cpu_s,tcp_error_max_m,energy_error_max,"
      "target_met";
  for (const std::string& joint : joints) {
    line += "," + CsvField("tracking_error_max:" + joint) + "," + CsvField("effort_peak:" + joint) +
            "," + CsvField("effort_rms:" + joint) + "," + CsvField("q_final:" + joint);
  }
  return line + ",message";
}

std::string SweepTableRow(const v1::RunInfo& info, const std::vector<std::string>& values) {
  const v1::RunStats& s = info.stats();
  std::string line = CsvField(info.id());
  for (const std::string& value : values) line += "," + CsvField(value);
  line += "," + std::string(v1::RunState_Name(info.state())) + "," + CsvField(s.trust()) + "," +
          results_csv::Number(s.t_reached_s()) + "," + std::to_string(info.frames()) + "," +
          std::to_string(s.steps()) + "," + results_csv::Number(s.cpu_s()) + "," +
          Figure(s.tcp_error_max_m()) + "," + Figure(s.energy_error_max()) + "," +
          (s.has_target_met() ? (s.target_met() ? "true" : "false") : "");
  const v1::RunSummary& summary = s.summary();
  for (int j = 0; j < info.num_dofs(); ++j) {
    if (j < summary.joints_size()) {
      const v1::JointSummary& joint = summary.joints(j);
      line += "," + Figure(joint.tracking_error_max()) + "," + Figure(joint.effort_peak()) + "," +
              Figure(joint.effort_rms());
    } else {
      line += ",,,";
    }
    line += "," + (j < summary.q_final_size() ? results_csv::Number(summary.q_final(j)) : "");
  }
  return line + "," + CsvField(info.message());
}

}  // namespace mbstream::cli
