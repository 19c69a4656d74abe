// The one-line progress of a sweep as the server reports it (GetSweep), for `mbstream sweep`.
#pragma once

#include <string>

#include "mbstream/v1/simulation_service.pb.h"

namespace mbstream::cli {

// "sweep s-...: 12/100 runs ended (FINISHED 10, CANCELLED 2), 30 queued, 2 running, 68 not
// started" (" - cancelled" once CancelSweep was called).
std::string SweepProgressLine(const v1::SweepProgress& progress);

}  // namespace mbstream::cli
