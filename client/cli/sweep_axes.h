// The CLI's way of saying what a sweep varies: `--grid PATH=START:STOP:COUNT[:log]` or
// `--grid PATH=V1,V2,...` per axis, or `--list FILE.csv` (a header of paths, a row per point).
#pragma once

#include <string>
#include <vector>

#include "mbstream/v1/simulation_service.pb.h"

namespace mbstream::cli {

// One --grid option as an axis: COUNT values evenly spaced from START to STOP (geometrically
// with :log, both then > 0), or the comma-separated values as given. Throws InputError
// naming the option and what to write.
v1::SweepAxis ParseGridAxis(const std::string& option);

// A --list file into `request` (list_paths, list): plain CSV, no quoted fields. Throws
// InputError naming the file and line.
void ReadSweepList(const std::string& path, v1::StartSweepRequest* request);

}  // namespace mbstream::cli
