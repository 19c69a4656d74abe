// The CSV text of the results files, shared by the writer of a whole result
// (results_files.h) and the one that streams frames as they come (results_stream.h), so the
// two give byte-identical files.
#pragma once

#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "server/sim/run_result.h"

namespace mbstream::results_csv {

// Appends x in the shortest form that reads back as the same double (std::to_chars).
void AppendNumber(std::string& out, double x);
std::string Number(double x);

// A CSV field (RFC 4180): quoted when it holds a comma, a quote or a line break.
std::string CsvField(const std::string& text);

// "t" and the joints' names in the model's joint order; `prefix` and the joint's number
// where a name is missing.
std::string JointHeader(const std::vector<std::string>& names, const std::string& prefix, int n);

// One row: t, then `width` values.
void AppendRow(std::string& out, double t, const double* values, int width);

// One series file of the results directory: its name, header and row width, and where frame
// k's values are in a RunResult.
struct Series {
  std::string file;  // "joints.csv", ...
  std::string header;
  int width = 0;
  std::function<void(const RunResult&, int k, double* row)> values;  // fills `width` values
};

// The series a result has: joints, velocities, tcp, then torques and energy when it has them,
// and loop_forces.csv when it has the cut joints' reactions.
std::vector<Series> SeriesOf(const RunResult& result);

// The series files that may be absent from a result (removed when stale).
inline const char* const kOptionalFiles[] = {"torques.csv", "energy.csv", "probes.csv",
                                             "loop_forces.csv", "contacts.csv"};

// contacts.csv (docs/contact.md): its header, and one row per record of `log` appended to `out`.
inline constexpr char kContactsHeader[] =
    "t,link_a,collision_a,link_b,collision_b,px,py,pz,nx,ny,nz,depth,normal_force,friction_x,"
    "friction_y,friction_z";
void AppendContactRows(std::string& out, const ContactLog& log);

// Writes path atomically: to path.tmp, then rename. Throws InputError naming the path.
void WriteFile(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

// Renames path.tmp to path; throws InputError naming it.
void CommitFile(const std::filesystem::path& path);

}  // namespace mbstream::results_csv
