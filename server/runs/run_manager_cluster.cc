// RunManager's answers about the cluster (docs/cluster.md, "Calls for runs on other
// replicas"): where a run integrates, for the service's proxies; the runs other replicas
// claim, for follow streams; models submitted to other replicas, and the runs claimed here
// that other replicas started.
#include <spdlog/spdlog.h>

#include "server/runs/cluster_follow.h"
#include "server/runs/request_error.h"
#include "server/runs/run_manager.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"

namespace mbstream {

RunManager::RunPlace RunManager::Locate(const std::string& run_id) const {
  RunPlace place;
  if (replica_.private_store) return place;  // every run is this server's
  if (queue_.IntegratesHere(run_id)) return place;
  std::optional<v1::RunInfo> stored = store_->GetRun(run_id);
  if (!stored) {
    place.info = Get(run_id);  // throws kNotFound (or found here meanwhile)
    return place;
  }
  place.info = std::move(*stored);
  if (IsFinalState(place.info.state())) {
    place.where = RunPlace::Where::kEnded;
  } else if (place.info.state() == v1::QUEUED) {
    place.where = RunPlace::Where::kQueued;
  } else if (place.info.replica() != replica_.id) {
    place.where = RunPlace::Where::kElsewhere;
  }
  return place;
}

std::shared_ptr<const CompiledModel> RunManager::FindModel(const std::string& model_ref) const {
  try {
    return models_->Find(model_ref);
  } catch (const RequestError& error) {
    if (error.kind() != RequestErrorKind::kNotFound) throw;
  }
  // Submitted to another replica since this one listed the store's models.
  if (models_->LoadStored() == 0) return models_->Find(model_ref);  // throws kNotFound again
  spdlog::info("models of other replicas loaded from the store for '{}'", model_ref);
  return models_->Find(model_ref);
}

std::shared_ptr<Run> RunManager::RunOf(const v1::RunInfo& info) {
  std::shared_ptr<const CompiledModel> model = FindModel(info.model_id());
  std::vector<std::string> warnings;
  const RunConfig config = PrepareConfig(*model, info.spec(), &warnings);
  return std::make_shared<Run>(info, config, std::move(model), *clock_, ProbeOptions());
}

void RunManager::RefreshModels() const {
  if (replica_.private_store) return;
  if (const int loaded = models_->LoadStored(); loaded > 0) {
    spdlog::info("{} models of other replicas listed from the store", loaded);
  }
}

v1::ModelInfo RunManager::ModelInfo(const std::string& id_or_name) const {
  try {
    return models_->Info(id_or_name);
  } catch (const RequestError& error) {
    if (error.kind() != RequestErrorKind::kNotFound || replica_.private_store) throw;
  }
  RefreshModels();
  return models_->Info(id_or_name);
}

}  // namespace mbstream
