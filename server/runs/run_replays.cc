// RunManager's replays of stored runs (run_replays.h; replay.proto): cursors, probe sets and
// replays to the follow streams.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "server/runs/request_error.h"
#include "server/runs/run_manager.h"
#include "server/runs/run_replays.h"
#include "server/store/store.h"
#include "shared/common/check.h"

namespace mbstream {

bool RunReplays::IsActive(const std::string& run_id) const {
  return m_.FindActive(run_id) != nullptr;
}

std::unique_ptr<ReplayCursor> RunReplays::Open(const v1::RunInfo& info) const {
  return std::make_unique<ReplayCursor>(m_.store_, info.id(), info.frames());
}

std::string RunReplays::NewProbeSetId() const {
  static thread_local std::mt19937_64 random(std::random_device{}());
  for (;;) {
    char id[32];
    std::snprintf(id, sizeof(id), "ps-%016llx", static_cast<unsigned long long>(random()));
    if (!m_.store_->GetProbeSet(id)) return id;
  }
}

std::unique_ptr<ProbeRecorder> RunReplays::RecordProbeSet(const v1::ProbeSet& set) const {
  auto recorder = std::make_unique<ProbeRecorder>(
      "probe set " + set.id() + " of run " + set.run_id(), *m_.clock_, m_.ProbeOptions());
  recorder->Open(
      [store = m_.store_, set, created = false](const std::vector<v1::ProbeReport>& batch) mutable {
        if (!created) {
          store->CreateProbeSet(set);
          created = true;
        }
        store->AddProbeSetReports(set.id(), batch);
        return true;
      });
  return recorder;
}

std::vector<v1::ProbeSet> RunReplays::ProbeSets(const std::string& run_id) const {
  (void)m_.Get(run_id);  // kNotFound for an unknown run
  return m_.store_->ListProbeSets(run_id);
}

std::vector<v1::ProbeReport> RunReplays::ProbeSetReports(const std::string& run_id,
                                                         const std::string& set_id) const {
  const std::optional<v1::ProbeSet> set = m_.store_->GetProbeSet(set_id);
  if (!set || set->run_id() != run_id) {
    throw RequestError(RequestErrorKind::kNotFound,
                       "run " + run_id + " has no probe set '" + set_id.substr(0, 64) +
                           "'; `mbstream probe-sets " + run_id + "` lists its sets");
  }
  return m_.store_->GetProbeSetReports(set_id);
}

v1::RunInfo RunReplays::ToFollowers(const std::string& run_id, double speed_x) {
  if (!std::isfinite(speed_x) || speed_x <= 0.0 || speed_x > 1000.0) {
    throw InputError("ReplayRun: speed " + std::to_string(speed_x) +
                     " is out of range; give a speed above 0 up to 1000 (1 = real time)");
  }
  v1::RunInfo info = m_.results_.Info(run_id);
  if (info.frames() < 1) {
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       "run " + run_id + " has no stored frames: there is nothing to replay");
  }
  if (m_.queue_.stop_reason()) {
    throw RequestError(RequestErrorKind::kUnavailable, "the server is shutting down");
  }
  const std::vector<std::shared_ptr<Subscription>> followers = m_.fan_out_.followers();
  m_.follower_replays_.Start(info, speed_x, followers);
  spdlog::info("run {} replayed to {} followers at {}x", run_id, followers.size(), speed_x);
  return info;
}

}  // namespace mbstream
