#include "server/results/results_files.h"

#include <nlohmann/json.hpp>

#include <charconv>
#include <filesystem>
#include <fstream>
#include <functional>
#include <system_error>

#include "common/check.h"

#ifndef MBSTREAM_VERSION
#define MBSTREAM_VERSION "unknown"
#endif

namespace mbstream {

namespace {

namespace fs = std::filesystem;

// Appends x in the shortest form that reads back as the same double (std::to_chars): exact,
// and several times faster than printf's "%.17g", which also writes digits beyond those that
// identify the double (0.1 as 0.10000000000000001).
void AppendNumber(std::string& out, double x) {
  char buffer[32];
  const std::to_chars_result written = std::to_chars(buffer, buffer + sizeof(buffer), x);
  MBSTREAM_CHECK(written.ec == std::errc());
  out.append(buffer, written.ptr);
}

std::string Number(double x) {
  std::string text;
  AppendNumber(text, x);
  return text;
}

// Writes path atomically: to path.tmp, then rename.
void WriteFile(const fs::path& path, const std::function<void(std::ostream&)>& write) {
  const fs::path temporary = path.string() + ".tmp";
  {
    std::ofstream out(temporary);
    if (!out) {
      throw InputError("cannot write " + temporary.string() +
                       ": check that the directory is writable");
    }
    write(out);
    out.flush();
    if (!out) throw InputError("writing " + temporary.string() + " failed: is the disk full?");
  }
  std::error_code error;
  fs::rename(temporary, path, error);
  if (error) throw InputError("cannot rename " + temporary.string() + ": " + error.message());
}

// A CSV with t and `width` columns per frame from a frame-major array.
void WriteSeries(const fs::path& path, const std::string& header, const RunResult& result,
                 const std::vector<double>& values, int width) {
  WriteFile(path, [&](std::ostream& out) {
    std::string text = header + '\n';
    text.reserve(text.size() + static_cast<size_t>(result.num_frames()) * (width + 1) * 24);
    for (int k = 0; k < result.num_frames(); ++k) {
      AppendNumber(text, result.t[k]);
      for (int j = 0; j < width; ++j) {
        text += ',';
        AppendNumber(text, values[k * width + j]);
      }
      text += '\n';
    }
    out << text;
  });
}

// A CSV field (RFC 4180): quoted when it holds a comma, a quote or a line break.
std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// "t" and the joints' names in the model's joint order (the order of stats.json's
// "joints"); `prefix` and the joint's number where a name is missing.
std::string JointHeader(const std::vector<std::string>& names, const std::string& prefix, int n) {
  std::string header = "t";
  for (int i = 0; i < n; ++i) {
    const bool named = i < static_cast<int>(names.size()) && !names[i].empty();
    header += "," + (named ? CsvField(names[i]) : prefix + std::to_string(i + 1));
  }
  return header;
}

nlohmann::json NumberOrNull(double value) {
  return value >= 0.0 ? nlohmann::json(value) : nlohmann::json(nullptr);
}

}  // namespace

std::string StatsJson(const RunResult& result, const RunProvenance& provenance) {
  const RunStats& s = result.stats;
  nlohmann::ordered_json j;
  j["status"] = RunStatusName(s.status);
  j["message"] = s.message;
  j["t_reached"] = s.t_reached;
  j["frames"] = result.num_frames();
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
  j["warnings"] = s.warnings;
  j["budget"] = {{"max_steps", s.max_steps}, {"max_cpu_s", s.max_cpu_s}};
  j["joints"] = result.joint_names;
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
  const int n = result.num_dofs;
  WriteSeries(dir / "joints.csv", JointHeader(result.joint_names, "q", n), result, result.q, n);
  WriteSeries(dir / "velocities.csv", JointHeader(result.joint_names, "qd", n), result, result.qd,
              n);
  WriteSeries(dir / "tcp.csv", "t,x,y,z", result, result.tcp, 3);
  if (result.has_torques) {
    WriteSeries(dir / "torques.csv", JointHeader(result.joint_names, "tau", n), result, result.tau,
                n);
  } else {
    fs::remove(dir / "torques.csv", error);  // never leave a stale file from another run
  }
  if (result.has_energy) {
    std::vector<double> energy;
    energy.reserve(result.kinetic.size() * 2);
    for (size_t k = 0; k < result.kinetic.size(); ++k) {
      energy.push_back(result.kinetic[k]);
      energy.push_back(result.potential[k]);
    }
    WriteSeries(dir / "energy.csv", "t,kinetic,potential", result, energy, 2);
  }
  if (!probes.empty()) {
    WriteFile(dir / "probes.csv", [&](std::ostream& out) {
      out << "seq,t,name,x,y,z,latency_us\n";
      for (const ProbeRecord& p : probes) {
        out << p.seq << ',' << Number(p.t) << ',' << CsvField(p.name) << ',' << Number(p.x) << ','
            << Number(p.y) << ',' << Number(p.z) << ',' << p.latency_us << '\n';
      }
    });
  } else {
    fs::remove(dir / "probes.csv", error);
  }
  WriteFile(dir / "stats.json", [&](std::ostream& out) { out << StatsJson(result, provenance); });
}

}  // namespace mbstream
