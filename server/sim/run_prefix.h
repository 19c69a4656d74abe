// The first frames of a joint-space run computed already, by a pilot of the same scene at a
// tolerance at least as tight (an accuracy target's pilot, server/choose/), with the pilot's
// integration still alive at the last of them: a run given them takes the frames as its own
// and takes the integration over, going on with its own tolerance from there, instead of
// integrating the same start again from order 1 and tiny steps (on a stiff servo BDF's
// start-up is half of a run's steps).
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "server/sim/run_result.h"

namespace mbstream {

struct JointIntegration;  // joint_integration.h

struct RunPrefix {
  int num_dofs = 0;
  std::vector<double> t;      // s, frame times: the continuing run's first output times
  std::vector<double> q, qd;  // frame-major, as RunResult
  std::vector<double> work;   // J per frame (RunResult::work); empty when not integrated
  double rtol = 0.0;          // the tolerance the frames were computed at
  const char* method = "";    // and the method ("bdf", ...)

  std::size_t frames() const { return t.size(); }
  // The integration, at the last frame's time, when `fits` accepts it (called under the lock;
  // it may retune the integration, and must leave it unchanged when it refuses); null
  // otherwise, the integration then left for another run, or once a run has taken it (only
  // one can).
  std::shared_ptr<JointIntegration> TakeIntegrationIf(
      const std::function<bool(JointIntegration&)>& fits) const;
  bool HasIntegration() const;

  mutable std::mutex mutex;
  mutable std::shared_ptr<JointIntegration> integration;
};

// A run's link to pilots, beside its RunConfig and never inside it (the config is a plain
// value of what was asked; this is live state, which only server/choose/ sets): `prefix`, the
// run's first frames computed already by a pilot of the same scene with the same method; a
// joint-space run whose first output times they all are takes them and the pilot's
// integration over and goes on from there, otherwise (another formulation, other times, the
// integration taken already) it starts at t = 0 as usual. `keep_integration`: a finished
// joint-space run hands its integration on in RunResult::integration (for MakePrefix).
struct PilotLink {
  std::shared_ptr<const RunPrefix> prefix;  // null: start at t = 0
  bool keep_integration = false;
};

// The frames of a finished joint-space result made with PilotLink::keep_integration, and
// its integration (moved out of `result`).
std::shared_ptr<RunPrefix> MakePrefix(RunResult& result, double rtol, const char* method);

// How many of `prefix`'s leading frames are at exactly the run's first output `times`.
std::size_t MatchingFrames(const RunPrefix& prefix, const std::vector<double>& times);

}  // namespace mbstream
