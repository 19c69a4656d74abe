// The size of one run, checked before it starts, by the server (mbstream-server's
// --max-duration, --max-output-frames) and `mbstream simulate` (the same flags, the same
// defaults) alike, so that the two agree on every input.
#pragma once

#include <cstdint>

#include "server/sim/run_config.h"

namespace mbstream {

struct RunSizeLimits {
  double max_duration_s = 24 * 3600.0;    // s, simulated time of one run
  int64_t max_output_frames = 2'000'000;  // frames of one run
};

// Throws LimitError (RESOURCE_EXHAUSTED on the wire) when `config` asks for a run longer
// than `limits` allow, naming the flag that raises the limit; throws InputError when the run
// would give more frames than `spec_max_output_frames` (the spec's own cap; 0 = none).
void CheckRunSize(const RunConfig& config, int64_t spec_max_output_frames,
                  const RunSizeLimits& limits);

}  // namespace mbstream
