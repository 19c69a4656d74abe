// RunManager: what replays of stored runs need (replay.proto): cursors and probe sets.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>

#include "server/runs/request_error.h"
#include "server/runs/run_manager.h"
#include "server/store/store.h"
#include "shared/common/check.h"

namespace mbstream {

bool RunManager::IsActive(const std::string& run_id) const { return FindActive(run_id) != nullptr; }

std::unique_ptr<ReplayCursor> RunManager::OpenReplay(const v1::RunInfo& info) const {
  return std::make_unique<ReplayCursor>(store_, info.id(), info.frames());
}

std::string RunManager::NewProbeSetId() const {
  static thread_local std::mt19937_64 random(std::random_device{}());
  for (;;) {
    char id[32];
    std::snprintf(id, sizeof(id), "ps-%016llx", static_cast<unsigned long long>(random()));
    if (!store_->GetProbeSet(id)) return id;
  }
}

ProbeRecorder::Options RunManager::ProbeOptions() const {
  ProbeRecorder::Options options;
  options.max_reports = limits_.max_probe_reports;
  options.interval = std::chrono::duration_cast<RunClock::TimePoint::duration>(
      std::chrono::duration<double>(std::max(limits_.frame_flush_s, 0.0)));
  return options;
}

std::unique_ptr<ProbeRecorder> RunManager::RecordProbeSet(const v1::ProbeSet& set) const {
  auto recorder = std::make_unique<ProbeRecorder>(
      "probe set " + set.id() + " of run " + set.run_id(), *clock_, ProbeOptions());
  recorder->Open(
      [store = store_, set, created = false](const std::vector<v1::ProbeReport>& batch) mutable {
        if (!created) {
          store->CreateProbeSet(set);
          created = true;
        }
        store->AddProbeSetReports(set.id(), batch);
        return true;
      });
  return recorder;
}

std::vector<v1::ProbeSet> RunManager::ListProbeSets(const std::string& run_id) const {
  (void)Get(run_id);  // kNotFound for an unknown run
  return store_->ListProbeSets(run_id);
}

std::vector<v1::ProbeReport> RunManager::ResultProbeSet(const std::string& run_id,
                                                        const std::string& set_id) const {
  const std::optional<v1::ProbeSet> set = store_->GetProbeSet(set_id);
  if (!set || set->run_id() != run_id) {
    throw RequestError(RequestErrorKind::kNotFound,
                       "run " + run_id + " has no probe set '" + set_id.substr(0, 64) +
                           "'; `mbstream probe-sets " + run_id + "` lists its sets");
  }
  return store_->GetProbeSetReports(set_id);
}

v1::RunInfo RunManager::ReplayToFollowers(const std::string& run_id, double speed_x) {
  if (!std::isfinite(speed_x) || speed_x <= 0.0 || speed_x > 1000.0) {
    throw InputError("ReplayRun: speed " + std::to_string(speed_x) +
                     " is out of range; give a speed above 0 up to 1000 (1 = real time)");
  }
  v1::RunInfo info = ResultInfo(run_id);
  if (info.frames() < 1) {
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       "run " + run_id + " has no stored frames: there is nothing to replay");
  }
  if (queue_.stop_reason()) {
    throw RequestError(RequestErrorKind::kUnavailable, "the server is shutting down");
  }
  const std::vector<std::shared_ptr<Subscription>> followers = fan_out_.followers();
  follower_replays_.Start(info, speed_x, followers);
  spdlog::info("run {} replayed to {} followers at {}x", run_id, followers.size(), speed_x);
  return info;
}

}  // namespace mbstream
