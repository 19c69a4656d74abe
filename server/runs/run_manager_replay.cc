// RunManager: what replays of stored runs need (replay.proto): cursors and probe sets.
#include <cstdio>
#include <random>

#include "server/runs/request_error.h"
#include "server/runs/run_manager.h"
#include "server/store/store.h"

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

void RunManager::CreateProbeSet(const v1::ProbeSet& set) { store_->CreateProbeSet(set); }

void RunManager::AddProbeSetReports(const std::string& set_id,
                                    const std::vector<v1::ProbeReport>& reports) {
  store_->AddProbeSetReports(set_id, reports);
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

}  // namespace mbstream
