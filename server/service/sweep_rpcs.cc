// GetSweep and CancelSweep: a sweep as a whole, from the store (RunSweeps::Get), so
// that any replica of a cluster answers for every replica's runs.
#include <chrono>

#include "server/runs/request_error.h"
#include "server/service/simulation_service.h"
#include "server/service/sweep_progress.h"
#include "server/wire/stats_conversion.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// How long CancelSweep waits for the sweep's runs to end (a cancelled run ends at its next
// step; a run on an unreachable replica may not).
constexpr auto kCancelWait = std::chrono::seconds(10);

// Waits until run `run` has ended or `until` passes; a run deleted meanwhile counts as ended.
void AwaitEnded(const RunManager& runs, v1::RunInfo run,
                std::chrono::steady_clock::time_point until) {
  try {
    while (!IsFinalState(run.state()) && std::chrono::steady_clock::now() < until) {
      run = runs.AwaitChange(run.id(), run.state(), until);
    }
  } catch (const RequestError& error) {
    if (error.kind() != RequestErrorKind::kNotFound) throw;
  }
}

}  // namespace

grpc::Status SimulationService::GetSweep(grpc::ServerContext* context,
                                         const v1::GetSweepRequest* request,
                                         v1::SweepProgress* response) {
  return Admit(*context, "GetSweep", [&]() -> grpc::Status {
    if (request->runs_from() < 0 || request->max_runs() < 0) {
      throw InputError("runs_from and max_runs must be 0 or more");
    }
    *response = SweepProgressOf(
        request->sweep_id(),
        runs_->sweeps().Get(request->sweep_id(), request->runs_from(), request->max_runs()),
        request->runs_from());
    return grpc::Status::OK;
  });
}

grpc::Status SimulationService::CancelSweep(grpc::ServerContext* context,
                                            const v1::CancelSweepRequest* request,
                                            v1::SweepProgress* response) {
  return Admit(*context, "CancelSweep", [&]() -> grpc::Status {
    const std::string& id = request->sweep_id();
    const RunSweeps::View view = runs_->sweeps().Get(id, 0, 1);  // kNotFound when unknown
    const bool admin = authorizer_->CallerHas(*context, Role::kAdmin);
    const std::string caller = authorizer_->CallerId(*context);
    std::vector<v1::RunInfo> runs =
        view.stored ? runs_->sweeps().Unfinished(id) : runs_->sweeps().Runs(id);
    auto refuse = [&](const std::string& what) {
      return grpc::Status(grpc::StatusCode::PERMISSION_DENIED,
                          "sweep " + id + " was started with another token (" + what +
                              "); only that token or an admin token may cancel it");
    };
    if (!admin && view.stored && !view.stored->owner.empty() && view.stored->owner != caller) {
      return refuse("its owner");
    }
    for (const v1::RunInfo& run : runs) {  // every run checked before any is cancelled
      if (!admin && !run.owner().empty() && run.owner() != caller) return refuse(run.id());
    }
    const auto until = std::chrono::steady_clock::now() + kCancelWait;
    // The mark first: no more points are queued from now on (Store::AddSweepRuns checks it in
    // the transaction that queues them). Twice: runs queued just before the mark are
    // cancelled (and marked) too.
    runs_->sweeps().MarkCancelled(id);
    for (int pass = 0; pass < 2; ++pass) {
      for (const v1::RunInfo& run : runs) {
        if (IsFinalState(run.state())) continue;
        v1::CancelRunRequest cancel;
        cancel.set_run_id(run.id());
        v1::RunInfo now;
        // CancelRun's own path: here, or forwarded to the replica integrating the run.
        if (grpc::Status status = CancelRun(context, &cancel, &now);
            !status.ok() && status.error_code() != grpc::StatusCode::NOT_FOUND) {
          return status;
        }
      }
      for (const v1::RunInfo& run : runs) AwaitEnded(*runs_, run, until);
      runs_->sweeps().MarkCancelled(id);
      runs = view.stored ? runs_->sweeps().Unfinished(id) : runs_->sweeps().Runs(id);
    }
    *response = SweepProgressOf(id, runs_->sweeps().Get(id, 0, 0), 0);
    response->set_cancelled(true);
    return grpc::Status::OK;
  });
}

}  // namespace mbstream
