// This replica as RunManager runs it (replica_control.h; docs/cluster.md, "Calls for runs on
// other replicas"): where a run integrates, for the service's proxies; models submitted to
// other replicas; the free space that gates new runs; draining and shutdown.
#include <spdlog/spdlog.h>

#include "server/runs/cluster_follow.h"
#include "server/runs/replica_control.h"
#include "server/runs/request_error.h"
#include "server/runs/run_manager.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"

namespace mbstream {

ReplicaControl::RunPlace ReplicaControl::Locate(const std::string& run_id) const {
  RunPlace place;
  if (m_.replica_.private_store) return place;  // every run is this server's
  if (m_.queue_.IntegratesHere(run_id)) return place;
  std::optional<v1::RunInfo> stored = m_.store_->GetRun(run_id);
  if (!stored) {
    place.info = m_.Get(run_id);  // throws kNotFound (or found here meanwhile)
    return place;
  }
  place.info = std::move(*stored);
  if (IsFinalState(place.info.state())) {
    place.where = RunPlace::Where::kEnded;
  } else if (place.info.state() == v1::QUEUED) {
    place.where = RunPlace::Where::kQueued;
  } else if (place.info.replica() != m_.replica_.id) {
    place.where = RunPlace::Where::kElsewhere;
  }
  return place;
}

void ReplicaControl::RefreshModels() const {
  if (m_.replica_.private_store) return;
  if (const int loaded = m_.models_->LoadStored(); loaded > 0) {
    spdlog::info("{} models of other replicas listed from the store", loaded);
  }
}

v1::ModelInfo ReplicaControl::ModelInfo(const std::string& id_or_name) const {
  try {
    return m_.models_->Info(id_or_name);
  } catch (const RequestError& error) {
    if (error.kind() != RequestErrorKind::kNotFound || m_.replica_.private_store) throw;
  }
  RefreshModels();
  return m_.models_->Info(id_or_name);
}

const std::string& ReplicaControl::id() const { return m_.replica_.id; }

void ReplicaControl::SetAdvertisedAddress(const std::string& address) {
  m_.queue_.SetAdvertisedAddress(address);
}

bool ReplicaControl::serving() const { return m_.queue_.serving(); }

void ReplicaControl::SetServingListener(std::function<void(bool)> listener) {
  m_.queue_.SetServingListener(std::move(listener));
}

bool ReplicaControl::shared_store() const { return !m_.replica_.private_store; }

void ReplicaControl::SetFreeSpaceSource(FreeSpaceSource source, std::string data_dir) {
  m_.free_space_source_ = std::move(source);
  m_.data_dir_ = std::move(data_dir);
}

void ReplicaControl::Shutdown(const std::string& reason) {
  m_.feeder_.Stop();                        // no more points queued
  if (!m_.queue_.Shutdown(reason)) return;  // shut down already
  m_.follower_replays_.Stop();
  if (m_.cluster_follow_) m_.cluster_follow_->Stop();
  for (const auto& follower : m_.fan_out_.followers()) follower->Close();
}

void ReplicaControl::Drain(std::chrono::duration<double> grace, const std::string& reason) {
  m_.queue_.Drain(grace);
  Shutdown(reason);
}

}  // namespace mbstream
