#include "server/results/results_csv.h"

#include <charconv>
#include <fstream>
#include <system_error>

#include "shared/common/check.h"

namespace mbstream::results_csv {

namespace fs = std::filesystem;

// Shortest round-trip form: exact, and several times faster than printf's "%.17g", which
// also writes digits beyond those that identify the double (0.1 as 0.10000000000000001).
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

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\r\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string JointHeader(const std::vector<std::string>& names, const std::string& prefix, int n) {
  std::string header = "t";
  for (int i = 0; i < n; ++i) {
    const bool named = i < static_cast<int>(names.size()) && !names[i].empty();
    header += "," + (named ? CsvField(names[i]) : prefix + std::to_string(i + 1));
  }
  return header;
}

void AppendRow(std::string& out, double t, const double* values, int width) {
  AppendNumber(out, t);
  for (int j = 0; j < width; ++j) {
    out += ',';
    AppendNumber(out, values[j]);
  }
  out += '\n';
}

std::vector<Series> SeriesOf(const RunResult& result) {
  const int n = result.num_dofs;
  const int nq = result.positions();  // n without free bodies
  const std::vector<std::string>& position_names =
      result.num_positions > 0 ? result.position_names : result.joint_names;
  const auto slice = [](const std::vector<double> RunResult::*array, int width) {
    return [array, width](const RunResult& r, int k, double* row) {
      const double* from = (r.*array).data() + static_cast<size_t>(k) * width;
      std::copy(from, from + width, row);
    };
  };
  std::vector<Series> series = {
      {"joints.csv", JointHeader(position_names, "q", nq), nq, slice(&RunResult::q, nq)},
      {"velocities.csv", JointHeader(result.joint_names, "qd", n), n, slice(&RunResult::qd, n)},
      {"tcp.csv", "t,x,y,z", 3, slice(&RunResult::tcp, 3)},
  };
  if (result.has_torques) {
    series.push_back(
        {"torques.csv", JointHeader(result.joint_names, "tau", n), n, slice(&RunResult::tau, n)});
  }
  if (result.has_energy) {
    series.push_back(
        {"energy.csv", "t,kinetic,potential", 2, [](const RunResult& r, int k, double* row) {
           row[0] = r.kinetic[k];
           row[1] = r.potential[k];
         }});
  }
  if (!result.loop_force_names.empty()) {
    // Force (N) then torque (N*m about the joint's origin) on the cut joint's child side from
    // its parent side, world frame (RunResult::loop_forces).
    std::string header = "t";
    for (const std::string& name : result.loop_force_names) {
      for (const char* part : {"fx", "fy", "fz", "tx", "ty", "tz"}) {
        header += ',' + CsvField(name + '.' + part);
      }
    }
    const int width = 6 * static_cast<int>(result.loop_force_names.size());
    series.push_back({"loop_forces.csv", header, width, slice(&RunResult::loop_forces, width)});
  }
  return series;
}

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
  CommitFile(path);
}

void CommitFile(const fs::path& path) {
  const fs::path temporary = path.string() + ".tmp";
  std::error_code error;
  fs::rename(temporary, path, error);
  if (error) throw InputError("cannot rename " + temporary.string() + ": " + error.message());
}

void AppendContactRows(std::string& out, const ContactLog& log) {
  for (const ContactRecord& r : log.records) {
    AppendNumber(out, r.t);
    for (const int g : {r.geometry_a, r.geometry_b}) {
      out += ',' + CsvField(log.link[g]) + ',' + CsvField(log.collision[g]);
    }
    for (const double x :
         {r.point[0], r.point[1], r.point[2], r.normal[0], r.normal[1], r.normal[2], r.depth,
          r.normal_force, r.friction[0], r.friction[1], r.friction[2]}) {
      out += ',';
      AppendNumber(out, x + 0.0);  // -0 as 0
    }
    out += '\n';
  }
}

}  // namespace mbstream::results_csv
