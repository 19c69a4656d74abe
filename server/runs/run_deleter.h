// Deleting runs and models (DeleteRuns, DeleteModel; retention.h deletes through it too): a
// queued or running run is cancelled first (RunManager::Cancel) and deleted once it has ended
// and its final state is stored; each run goes in one store transaction (Store::DeleteRun),
// then this replica forgets what it kept of it in memory. A reader of a deleted run gets
// NOT_FOUND or its whole result (get_result.cc checks the run is still stored after it read
// everything). gRPC-free: the service calls it.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "mbstream/v1/model.pb.h"
#include "mbstream/v1/run.pb.h"

namespace mbstream {

class Store;
class RunManager;
class ModelRegistry;

class RunDeleter {
 public:
  // None is owned; all must outlive the deleter. `stop_wait`: how long a cancelled run may
  // take to end before its deletion is given up (kUnavailable).
  RunDeleter(Store* store, RunManager* runs, ModelRegistry* models,
             std::chrono::duration<double> stop_wait = std::chrono::seconds(60));

  // Deletes every run of `run_ids`, in order, each in its own transaction. Each is looked up
  // first: RequestError(kNotFound) naming an unknown one, and nothing is deleted. Returns the
  // runs as they were just before deletion (ended). Throws RequestError(kFailedPrecondition)
  // for a run integrating on another replica of a shared store (cancel it there first), and
  // kUnavailable when a cancelled run does not end within stop_wait.
  std::vector<v1::RunInfo> DeleteRuns(const std::vector<std::string>& run_ids) const;

  // Deletes model `model` (id or name). With `with_runs`, its runs first (as DeleteRuns,
  // returned in `deleted_runs`); without, RequestError(kFailedPrecondition) naming how many
  // runs it has. A built-in model is refused (kFailedPrecondition: it is loaded again at every
  // start). Throws RequestError(kNotFound) for an unknown model.
  v1::ModelInfo DeleteModel(const std::string& model, bool with_runs,
                            std::vector<v1::RunInfo>* deleted_runs) const;

  // Marks ended run `run_id` to be kept from retention (or no longer) and returns its stored
  // info. RequestError: kNotFound, kFailedPrecondition while it is queued or running.
  v1::RunInfo SetKeep(const std::string& run_id, bool keep) const;

  // Deletes ended run `run_id` unless it is kept or not ended (retention.h): true when it
  // was deleted. Reads the run again first: a run marked keep meanwhile stays.
  bool DeleteIfEnded(const std::string& run_id) const;

 private:
  // Cancels `info`'s run when it has not ended and waits for its end; returns it ended.
  v1::RunInfo StopRun(const v1::RunInfo& info) const;
  // Deletes ended run `run_id` from the store and the memory of this replica.
  void Remove(const std::string& run_id) const;

  Store* store_;
  RunManager* runs_;
  ModelRegistry* models_;
  std::chrono::duration<double> stop_wait_;
};

}  // namespace mbstream
