// This replica, as RunManager runs it (replica_control.cc; docs/cluster.md): its id, the
// address it advertises (set once the server listens), whether it should get calls (the
// store answered the keeper's last look and it is neither draining nor stopping), where a
// run integrates for the service's proxies, the models other replicas submitted, the disk
// whose free space gates new runs, and its end: Drain and Shutdown.
#pragma once

#include <chrono>
#include <functional>
#include <string>

#include "mbstream/v1/model.pb.h"
#include "mbstream/v1/run.pb.h"
#include "server/runs/free_space.h"

namespace mbstream {

class RunManager;

class ReplicaControl {
 public:
  ReplicaControl(const ReplicaControl&) = delete;
  ReplicaControl& operator=(const ReplicaControl&) = delete;

  const std::string& id() const;
  void SetAdvertisedAddress(const std::string& address);
  bool serving() const;
  // `listener` is called with each change of serving() (from the keeper's thread or Drain's
  // caller), and at once with the present value.
  void SetServingListener(std::function<void(bool)> listener);
  bool shared_store() const;

  // Where run `run_id` integrates: here (with a private store: always, and the store is not
  // read), queued in a shared store (any replica may claim it), on another replica (`info`,
  // from the store, names it: replica, replica_address) or ended. Throws
  // RequestError(kNotFound).
  struct RunPlace {
    enum class Where { kHere, kQueued, kElsewhere, kEnded };
    Where where = Where::kHere;
    v1::RunInfo info;
  };
  RunPlace Locate(const std::string& run_id) const;
  // Models submitted to other replicas: with a shared store, the store's model list is read
  // again (not compiled: a model is compiled when a run first needs it).
  void RefreshModels() const;
  // A model's info by id or name, reading the store's list again once when it is unknown
  // here (shared store). Throws as ModelRegistry::Info.
  v1::ModelInfo ModelInfo(const std::string& id_or_name) const;

  // Where new runs learn the free space of the disk of `data_dir` (the SQLite store's data
  // directory), checked against limits().min_free_bytes before any run is queued
  // (free_space.h). Unset (a PostgreSQL store): no check. Call before the first Start.
  void SetFreeSpaceSource(FreeSpaceSource source, std::string data_dir);

  // Stops accepting runs, interrupts queued and running ones (state INTERRUPTED, frames so
  // far stored; with a shared store, queued runs stay queued and running ones with retries
  // left are queued again), closes every subscription and joins the workers. Idempotent.
  void Shutdown(const std::string& reason);
  // Drains the replica: stops claiming runs, waits up to `grace` for the runs integrating
  // here to end, then Shutdown(reason) (what still runs is handed back).
  void Drain(std::chrono::duration<double> grace, const std::string& reason);

 private:
  friend class RunManager;
  explicit ReplicaControl(RunManager& manager) : m_(manager) {}
  RunManager& m_;
};

}  // namespace mbstream
