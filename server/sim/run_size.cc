#include "server/sim/run_size.h"

#include <string>

#include "server/sim/simulate.h"
#include "shared/common/check.h"
#include "shared/common/format.h"

namespace mbstream {

void CheckRunSize(const RunConfig& config, int64_t spec_max_output_frames,
                  const RunSizeLimits& limits) {
  if (config.duration > limits.max_duration_s) {
    throw LimitError("spec.duration_s " + FormatString("%.6g", config.duration) +
                     " s exceeds the limit of " + FormatString("%.6g", limits.max_duration_s) +
                     " s (--max-duration); shorten the run or raise the limit");
  }
  const int64_t frames = OutputFrameCount(config.duration, config.output_interval);
  if (spec_max_output_frames > 0 && frames > spec_max_output_frames) {
    throw InputError("spec.max_output_frames is " + std::to_string(spec_max_output_frames) +
                     " but duration_s / output_interval_s gives " + std::to_string(frames) +
                     " frames; raise max_output_frames or lengthen output_interval_s");
  }
  if (frames > limits.max_output_frames) {
    throw LimitError("the run would produce " + std::to_string(frames) +
                     " frames, more than the limit of " + std::to_string(limits.max_output_frames) +
                     " (--max-output-frames); lengthen spec.output_interval_s, shorten "
                     "spec.duration_s or raise the limit");
  }
}

}  // namespace mbstream
