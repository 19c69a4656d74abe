#include "server/results/results_files.h"

#include <nlohmann/json.hpp>

#include <charconv>
#include <filesystem>
#include <fstream>
#include <functional>
#include <system_error>

#include "server/results/results_csv.h"
#include "shared/common/check.h"

#ifndef MBSTREAM_VERSION
#define MBSTREAM_VERSION "unknown"
#endif

namespace mbstream {

namespace {

namespace fs = std::filesystem;
using results_csv::Number;

// contacts.csv: one row per contact per output frame (docs/contact.md), world frame.
void WriteContactsCsv(const ContactLog& log, const fs::path& path) {
  results_csv::WriteFile(path, [&](std::ostream& out) {
    std::string text = std::string(results_csv::kContactsHeader) + '\n';
    results_csv::AppendContactRows(text, log);
    out << text;
  });
}

nlohmann::json NumberOrNull(double value) {
  return value >= 0.0 ? nlohmann::json(value) : nlohmann::json(nullptr);
}

// Over every frame the run computed: which it kept, which it dropped, the final state and
// each joint's effort and tracking figures (null where the run has none).
nlohmann::ordered_json SummaryJson(const RunSummary& s, const std::vector<std::string>& names) {
  nlohmann::ordered_json joints = nlohmann::ordered_json::array();
  for (size_t j = 0; j < s.joints.size(); ++j) {
    joints.push_back({{"joint", j < names.size() ? names[j] : std::to_string(j)},
                      {"effort_peak", NumberOrNull(s.joints[j].effort_peak)},
                      {"effort_rms", NumberOrNull(s.joints[j].effort_rms)},
                      {"tracking_error_max", NumberOrNull(s.joints[j].tracking_error_max)}});
  }
  return {{"keep", s.keep},
          {"frames_computed", s.frames_computed},
          {"frames_kept", s.frames_kept},
          {"frames_dropped", s.frames_computed - s.frames_kept},
          {"t_final", s.t_final},
          {"q_final", s.q_final},
          {"qd_final", s.qd_final},
          {"joints", joints}};
}

}  // namespace

std::string StatsJson(const RunResult& result, const RunProvenance& provenance, long frames) {
  const RunStats& s = result.stats;
  nlohmann::ordered_json j;
  j["status"] = RunStatusName(s.status);
  j["message"] = s.message;
  j["t_reached"] = s.t_reached;
  j["frames"] = frames >= 0 ? frames : result.num_frames();
  j["formulation"] = s.formulation;
  j["formulation_reason"] = s.formulation_reason;
  j["equations"] = s.equations;
  j["jacobian_nnz"] = s.jacobian_nnz;
  j["method"] = s.method;
  j["integrator"] = s.integrator;
  j["steps"] = s.solver.steps;
  j["rhs_evals"] = s.solver.rhs_evals;
  j["jac_evals"] = s.solver.jac_evals;
  j["nonlinear_iterations"] = s.solver.nonlinear_iterations;
  j["error_test_failures"] = s.solver.error_test_failures;
  j["convergence_failures"] = s.solver.convergence_failures;
  j["cpu_s"] = s.cpu_s;
  j["wall_s"] = s.wall_s;
  j["accuracy"] = {
      {"tcp_error_max_m", NumberOrNull(s.tcp_error_max)},
      {"energy_error_max_rel", NumberOrNull(s.energy_error_max)},
      {"energy_work_approximate", s.energy_work_approximate},
      {"energy_work",
       s.energy_work.empty() ? nlohmann::json(nullptr) : nlohmann::json(s.energy_work)},
      {"drift_position_max_m", NumberOrNull(s.drift_position_max)},
      {"drift_orientation_max_rad", NumberOrNull(s.drift_orientation_max)},
      {"drift_velocity_max", NumberOrNull(s.drift_velocity_max)},
      {"quaternion_norm_error_max", NumberOrNull(s.quaternion_norm_error_max)},
  };
  j["trust"] = s.trust == Trust::kNotAssessed ? nlohmann::ordered_json(nullptr)
                                              : nlohmann::ordered_json(TrustName(s.trust));
  j["trust_reason"] = s.trust_reason;
  j["target_met"] =
      s.target_met ? nlohmann::ordered_json(*s.target_met) : nlohmann::ordered_json(nullptr);
  j["choice"] = s.choice_json.empty() ? nlohmann::ordered_json(nullptr)
                                      : nlohmann::ordered_json::parse(s.choice_json);
  j["loops"] = nullptr;
  if (!s.loops.cut_joints.empty()) {
    j["loops"] = {{"cut_joints", s.loops.cut_joints},
                  {"equations", s.loops.equations},
                  {"independent", s.loops.independent},
                  {"redundant", s.loops.equations - s.loops.independent},
                  {"mobility", s.loops.mobility},
                  {"assembly", s.loops.assembly},
                  {"position_residual_max_m", NumberOrNull(s.drift_position_max)},
                  {"orientation_residual_max_rad", NumberOrNull(s.drift_orientation_max)},
                  {"velocity_residual_max", NumberOrNull(s.drift_velocity_max)}};
  }
  j["summary"] = SummaryJson(s.summary, result.joint_names);
  j["warnings"] = s.warnings;
  j["budget"] = {{"max_steps", s.max_steps}, {"max_cpu_s", s.max_cpu_s}};
  if (s.contact.active) {  // docs/contact.md
    j["contact"] = {{"penetration_max_m", s.contact.penetration_max_m},
                    {"contacts_peak", s.contact.contacts_peak},
                    {"penetration_relative_max", s.contact.penetration_relative_max},
                    {"dissipated_work_j", s.contact.dissipated_work_j}};
  }
  j["joints"] = result.joint_names;
  if (result.num_positions > 0) j["positions"] = result.position_names;  // free bodies
  j["reproduce"] = {
      {"mbstream_version", MBSTREAM_VERSION},
      {"model", provenance.model_name},
      {"model_source", provenance.model_source},
      {"model_id", provenance.model_id.empty() ? nlohmann::ordered_json(nullptr)
                                               : nlohmann::ordered_json(provenance.model_id)},
      {"run_id", provenance.run_id.empty() ? nlohmann::ordered_json(nullptr)
                                           : nlohmann::ordered_json(provenance.run_id)},
      {"spec", provenance.spec_json.empty() ? nlohmann::ordered_json(nullptr)
                                            : nlohmann::ordered_json::parse(provenance.spec_json)},
  };
  return j.dump(2) + "\n";
}

void WriteResultsDirectory(const RunResult& result, const RunProvenance& provenance,
                           const std::string& directory, const std::vector<ProbeRecord>& probes) {
  const fs::path dir(directory);
  std::error_code error;
  fs::create_directories(dir, error);
  if (error) {
    throw InputError("cannot create results directory " + directory + ": " + error.message());
  }
  for (const results_csv::Series& series : results_csv::SeriesOf(result)) {
    results_csv::WriteFile(dir / series.file, [&](std::ostream& out) {
      std::string text = series.header + '\n';
      text.reserve(text.size() +
                   static_cast<size_t>(result.num_frames()) * (series.width + 1) * 24);
      std::vector<double> row(series.width);
      for (int k = 0; k < result.num_frames(); ++k) {
        series.values(result, k, row.data());
        results_csv::AppendRow(text, result.t[k], row.data(), series.width);
      }
      out << text;
    });
  }
  if (!result.has_torques) fs::remove(dir / "torques.csv", error);  // never leave a stale file
  if (!result.has_energy) fs::remove(dir / "energy.csv", error);
  if (result.loop_force_names.empty()) fs::remove(dir / "loop_forces.csv", error);
  if (result.contacts.active && result.contacts.keep_records) {
    WriteContactsCsv(result.contacts, dir / "contacts.csv");
  } else {
    fs::remove(dir / "contacts.csv", error);
  }
  if (!probes.empty()) {
    results_csv::WriteFile(dir / "probes.csv", [&](std::ostream& out) {
      out << "seq,t,name,x,y,z,latency_us\n";
      for (const ProbeRecord& p : probes) {
        out << p.seq << ',' << Number(p.t) << ',' << results_csv::CsvField(p.name) << ','
            << Number(p.x) << ',' << Number(p.y) << ',' << Number(p.z) << ',' << p.latency_us
            << '\n';
      }
    });
  } else {
    fs::remove(dir / "probes.csv", error);
  }
  results_csv::WriteFile(dir / "stats.json",
                         [&](std::ostream& out) { out << StatsJson(result, provenance); });
}

}  // namespace mbstream
