// A sweep's progress as a whole (GetSweep, CancelSweep) from its runs.
#pragma once

#include <string>
#include <vector>

#include "mbstream/v1/simulation_service.pb.h"

namespace mbstream {

// `runs`: the sweep's runs in point order (RunManager::SweepRuns).
v1::SweepProgress SweepProgressOf(const std::string& sweep_id,
                                  const std::vector<v1::RunInfo>& runs);

// Whether a run of `runs` carries the mark of a cancelled sweep (RunInfo.sweep_cancelled).
bool SweepWasCancelled(const std::vector<v1::RunInfo>& runs);

}  // namespace mbstream
