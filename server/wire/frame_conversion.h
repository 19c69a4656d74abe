// Output frames between the core's RunResult (frame-major arrays) and v1::Frame messages.
#pragma once

#include <vector>

#include "mbstream/v1/frame.pb.h"
#include "mbstream/v1/run.pb.h"
#include "server/sim/run_result.h"

namespace mbstream {

// Frame `k` of `result` as a message with sequence number k. Frame.tau holds the drive
// efforts (num_dofs values, when the run computes them; Frame.q has RunResult::positions()),
// then, for a run with closed loops
// that reports them (RunSpec.report_loop_forces), the cut joints' reactions (6 each,
// RunResult::loop_forces). Every number must be finite
// (the engine only keeps good frames); a non-finite one is a bug and throws InternalError,
// so no NaN ever leaves the server.
void FrameToProto(const RunResult& result, int k, v1::Frame* frame);

// Rebuilds a RunResult from a run's info (joint names, flags, statistics) and its frames in
// sequence order: the inverse of FrameToProto, bit for bit (the cut joints' reactions named
// from RunStats.loops.cut_joints). Throws InputError naming the frame when a frame's arrays
// do not match the run's joint count.
RunResult ResultFromFrames(const v1::RunInfo& info, const std::vector<v1::Frame>& frames);

}  // namespace mbstream
