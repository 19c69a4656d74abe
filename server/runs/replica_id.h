// A replica's id when none is given: "<host>-<process id>-<4 hex digits>", unique among the
// replicas on one store (RunInfo.replica).
#pragma once

#include <string>

namespace mbstream {

std::string NewReplicaId();

}  // namespace mbstream
