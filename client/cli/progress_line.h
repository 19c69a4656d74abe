// The one-line live progress of `mbstream run --watch`.
#pragma once

#include <string>

#include "mbstream/v1/run.pb.h"

namespace mbstream::cli {

// "r-... RUNNING t = 12.350/20.000 s  61.8%  1.00x real time  ETA 7.6 s"; `elapsed_s` is the
// wall time since the watch saw the run start.
std::string ProgressLine(const v1::RunInfo& info, double elapsed_s);

}  // namespace mbstream::cli
