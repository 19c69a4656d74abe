#include "server/service/storage_keeper.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <map>

#include "server/runs/free_space_watch.h"
#include "server/runs/model_registry.h"
#include "server/runs/request_error.h"
#include "server/runs/retention.h"
#include "server/store/store.h"

namespace mbstream {

namespace {

// The models with runs or stored bytes, most bytes first, with their own retention limits
// (`policy`: null without retention).
void AddModels(const StoreUsage& usage, const Store::ModelSizes& sizes,
               const std::map<std::string, std::string>& names, const RetentionPolicy* policy,
               v1::GetStorageResponse& report) {
  std::map<std::string, v1::StorageModelUsage> models;
  for (const auto& [id, used] : usage.models) {
    v1::StorageModelUsage& model = models[id];
    model.set_runs(used.runs);
    model.set_frame_bytes(used.frame_bytes);
    model.set_probe_bytes(used.probe_bytes);
  }
  for (const auto& [id, bytes] : sizes) models[id].set_model_bytes(bytes);
  std::vector<v1::StorageModelUsage> sorted;
  for (auto& [id, model] : models) {
    model.set_model_id(id);
    if (auto name = names.find(id); name != names.end()) model.set_model_name(name->second);
    if (policy != nullptr) {
      auto own = policy->models.find(model.model_name());
      if (own == policy->models.end()) own = policy->models.find(id);
      if (own != policy->models.end()) {
        model.set_own_retention(true);
        model.set_retain_runs(static_cast<int32_t>(own->second.retain_runs));
        model.set_retain_days(own->second.retain_days);
      }
    }
    sorted.push_back(std::move(model));
  }
  const auto total = [](const v1::StorageModelUsage& m) {
    return m.frame_bytes() + m.probe_bytes() + m.model_bytes();
  };
  std::stable_sort(sorted.begin(), sorted.end(),
                   [&](const auto& a, const auto& b) { return total(a) > total(b); });
  for (v1::StorageModelUsage& model : sorted) *report.add_models() = std::move(model);
}

}  // namespace

v1::GetStorageResponse StorageKeeper::Report() const {
  v1::GetStorageResponse report;
  report.set_backend(setup_.sqlite ? "sqlite" : "postgresql");
  report.set_location(setup_.location);
  std::vector<std::string> doomed;  // what retention would delete now
  if (setup_.retention != nullptr) {
    report.set_retain_runs(static_cast<int32_t>(setup_.retention->policy().retain_runs));
    report.set_retain_days(setup_.retention->policy().retain_days);
    for (const v1::RunInfo& run : setup_.retention->Plan()) doomed.push_back(run.id());
  }
  const StoreUsage usage = setup_.store->Usage(doomed);
  report.set_frame_bytes(usage.frame_bytes);
  report.set_probe_bytes(usage.probe_bytes);
  report.set_run_bytes(usage.run_bytes);
  report.set_disk_bytes(usage.disk_bytes);
  report.set_retention_runs(static_cast<int64_t>(doomed.size()));
  report.set_retention_bytes(usage.weighed_bytes);
  for (const auto& [state, runs] : usage.runs_by_state) {
    v1::StorageRunCount& count = *report.add_runs();
    count.set_state(static_cast<v1::RunState>(state));
    count.set_runs(runs);
  }
  const Store::ModelSizes sizes = setup_.store->ModelBytes();
  int64_t model_bytes = 0;
  for (const auto& [id, bytes] : sizes) model_bytes += bytes;
  report.set_model_bytes(model_bytes);
  std::map<std::string, std::string> names;
  if (setup_.models != nullptr) {
    for (const v1::ModelInfo& info : setup_.models->List()) names[info.id()] = info.name();
  }
  AddModels(usage, sizes, names,
            setup_.retention != nullptr ? &setup_.retention->policy() : nullptr, report);
  report.set_free_bytes(-1);
  if (setup_.free_space != nullptr) {
    report.set_below_min_free(!setup_.free_space->Check());
    report.set_free_bytes(setup_.free_space->free_bytes().value_or(-1));
    report.set_min_free_bytes(setup_.free_space->min_free_bytes());
  }
  return report;
}

v1::BackupStorageResponse StorageKeeper::Backup(const std::string& dir) const {
  if (!setup_.sqlite) {
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       "this server's store is PostgreSQL (" + setup_.location +
                           "): back it up with pg_dump (docs/cluster.md), not BackupStorage");
  }
  const auto start = std::chrono::steady_clock::now();
  const StoreBackup backup = setup_.store->Backup(dir);
  v1::BackupStorageResponse response;
  response.set_dir(backup.dir);
  response.set_database_bytes(backup.database_bytes);
  response.set_frames_bytes(backup.frames_bytes);
  response.set_runs(backup.runs);
  response.set_seconds(
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  spdlog::info("backup of {} runs in {}: database {} bytes, frames {} bytes, {:.2f} s", backup.runs,
               backup.dir, backup.database_bytes, backup.frames_bytes, response.seconds());
  return response;
}

}  // namespace mbstream
