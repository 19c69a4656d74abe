#include "server/runs/run_deleter.h"

#include <spdlog/spdlog.h>

#include "server/runs/model_registry.h"
#include "server/runs/request_error.h"
#include "server/runs/run_manager.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"
#include "shared/common/check.h"

namespace mbstream {

RunDeleter::RunDeleter(Store* store, RunManager* runs, ModelRegistry* models,
                       std::chrono::duration<double> stop_wait)
    : store_(store), runs_(runs), models_(models), stop_wait_(stop_wait) {
  MBSTREAM_CHECK(store_ != nullptr && runs_ != nullptr && models_ != nullptr);
}

v1::RunInfo RunDeleter::StopRun(const v1::RunInfo& info) const {
  if (IsFinalState(info.state())) return info;
  v1::RunInfo now = runs_->Cancel(info.id());  // kFailedPrecondition: on another replica
  const auto until = std::chrono::steady_clock::now() +
                     std::chrono::duration_cast<std::chrono::steady_clock::duration>(stop_wait_);
  while (!IsFinalState(now.state())) {
    if (std::chrono::steady_clock::now() >= until) {
      throw RequestError(RequestErrorKind::kUnavailable,
                         "run " + info.id() + " was cancelled but is still " +
                             v1::RunState_Name(now.state()) + " after " +
                             std::to_string(stop_wait_.count()) +
                             " s; it was not deleted: delete it again once it has ended");
    }
    now = runs_->AwaitChange(info.id(), now.state(), until);
  }
  return now;
}

void RunDeleter::Remove(const std::string& run_id) const {
  runs_->results().Forget(run_id);
  const bool deleted = store_->DeleteRun(run_id);
  runs_->results().Forget(run_id);  // a result kept between the two (never once the row is gone)
  spdlog::info("run {} deleted{}", run_id, deleted ? "" : " (it was gone already)");
}

std::vector<v1::RunInfo> RunDeleter::DeleteRuns(const std::vector<std::string>& run_ids) const {
  if (run_ids.empty()) throw InputError("no run to delete; name at least one run id");
  std::vector<v1::RunInfo> found;
  found.reserve(run_ids.size());
  for (const std::string& id : run_ids) found.push_back(runs_->Get(id));  // kNotFound first
  std::vector<v1::RunInfo> deleted;
  deleted.reserve(found.size());
  for (const v1::RunInfo& info : found) {
    deleted.push_back(StopRun(info));
    Remove(info.id());
  }
  return deleted;
}

v1::ModelInfo RunDeleter::DeleteModel(const std::string& model, bool with_runs,
                                      std::vector<v1::RunInfo>* deleted_runs) const {
  const v1::ModelInfo info =
      runs_->replica().ModelInfo(model);  // kNotFound (a shared store read again)
  if (info.builtin()) {
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       "model " + info.id() + " '" + info.name() +
                           "' is built in: the server loads it from its models directory at "
                           "every start; remove its folder there instead (its runs can be "
                           "deleted with `mbstream delete RUN...`)");
  }
  std::vector<std::string> run_ids;
  for (const v1::RunInfo& run : store_->ListRuns()) {
    if (run.model_id() == info.id()) run_ids.push_back(run.id());
  }
  if (!run_ids.empty() && !with_runs) {
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       "model " + info.id() + " '" + info.name() + "' still has " +
                           std::to_string(run_ids.size()) +
                           " runs; delete them first, or together with it "
                           "(mbstream delete --model " +
                           info.id() + " --with-runs)");
  }
  if (!run_ids.empty()) {
    std::vector<v1::RunInfo> runs = DeleteRuns(run_ids);
    if (deleted_runs != nullptr) *deleted_runs = std::move(runs);
  }
  if (const int64_t left = store_->DeleteModel(info.id()); left > 0) {  // runs started meanwhile
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       "model " + info.id() + " got " + std::to_string(left) +
                           " new runs while it was being deleted; it was kept: delete it again");
  }
  models_->Forget(info.id());
  spdlog::info("model {} '{}' deleted", info.id(), info.name());
  return info;
}

v1::RunInfo RunDeleter::SetKeep(const std::string& run_id, bool keep) const {
  const v1::RunInfo info = runs_->Get(run_id);  // kNotFound
  if (!IsFinalState(info.state())) {
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       "run " + run_id + " is " + v1::RunState_Name(info.state()) +
                           "; mark it once it has ended (retention deletes ended runs only)");
  }
  if (!store_->SetRunKeep(run_id, keep))
    throw RequestError(RequestErrorKind::kNotFound, "no run " + run_id + " (deleted)");
  runs_->results().Forget(run_id);  // its info kept in memory lacks the mark: read from the store
  std::optional<v1::RunInfo> stored = store_->GetRun(run_id);
  if (!stored) throw RequestError(RequestErrorKind::kNotFound, "no run " + run_id + " (deleted)");
  spdlog::info("run {} {}", run_id, keep ? "kept from retention" : "no longer kept");
  return *stored;
}

bool RunDeleter::DeleteIfEnded(const std::string& run_id) const {
  const std::optional<v1::RunInfo> info = store_->GetRun(run_id);
  if (!info || info->keep() || !IsFinalState(info->state()) || runs_->replays().IsActive(run_id)) {
    return false;
  }
  Remove(run_id);
  return true;
}

}  // namespace mbstream
