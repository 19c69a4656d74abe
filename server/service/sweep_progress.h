// A sweep's progress as a whole (GetSweep, CancelSweep) from RunSweeps::Get.
#pragma once

#include <string>

#include "mbstream/v1/simulation_service.pb.h"
#include "server/runs/run_manager.h"

namespace mbstream {

// `runs_from`: the point of view.runs' first run (GetSweepRequest.runs_from).
v1::SweepProgress SweepProgressOf(const std::string& sweep_id, const RunSweeps::View& view,
                                  int runs_from);

}  // namespace mbstream
