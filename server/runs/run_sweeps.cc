// RunManager's sweeps (run_sweeps.h; docs/cluster.md, "Sweeps"). A sweep the server feeds: Start
// checks and stores it whole and queues its first window; the feeder (sweep_feeder.h) queues the
// next points as its runs end, here or on any replica sharing the store, each point's run expanded
// from the stored definition (sweep_plan.h) and stored with the move of the sweep's next point
// in one transaction (Store::AddSweepRuns). Reads: a sweep's counts and a page of its runs,
// every replica's (the store's indexes of sweep ids), and the mark that it was cancelled.
#include <spdlog/spdlog.h>

#include <algorithm>

#include "server/runs/request_error.h"
#include "server/runs/run.h"
#include "server/runs/run_manager.h"
#include "server/runs/run_sweeps.h"
#include "server/runs/sweep_coordinates.h"
#include "server/runs/timed_id.h"
#include "server/runs/unix_time.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// Thrown by Feed's store call when the store refuses the points: nothing is queued.
struct SweepPointsRefused {};

}  // namespace

RunSweeps::Started RunSweeps::Start(const std::string& model_ref, v1::SweepDefinition definition,
                                    int window, const std::string& owner) {
  std::shared_ptr<const CompiledModel> model = m_.FindModel(model_ref);
  if (window < 0 || window > m_.limits_.max_queued_runs) {
    throw InputError("window is " + std::to_string(window) + "; give 1.." +
                     std::to_string(m_.limits_.max_queued_runs) +
                     " (this server's run queue), or 0 for 32");
  }
  if (window == 0) window = std::min(32, m_.limits_.max_queued_runs);
  ResolveCoordinatePaths(model->model, &definition);  // initial_q[box::link.z]
  auto plan = std::make_shared<const SweepPlan>(std::move(definition));
  const long total = plan->size();
  // Every point's values against the spec's fields (a bad value fails the sweep before any
  // run starts), one point at a time; the first window's against the model too.
  for (long k = 0; k < total; ++k) {
    const v1::RunSpec spec = plan->Spec(k, "sweep");
    if (k < window) {
      std::vector<std::string> warnings;
      try {
        m_.PrepareConfig(*model, spec, &warnings);
      } catch (const InputError& error) {
        throw InputError("sweep: point " + std::to_string(k) + " (" + plan->Label(k) +
                         "): " + error.what());
      } catch (const RequestError& error) {
        throw RequestError(error.kind(), "sweep: point " + std::to_string(k) + " (" +
                                             plan->Label(k) + "): " + error.what());
      }
    }
  }
  CheckFreeSpace(m_.free_space_source_, m_.limits_.min_free_bytes, m_.data_dir_);
  StoredSweep sweep;
  sweep.model_id = model->info.id();
  sweep.owner = owner;
  sweep.created_unix_ms = NowUnixMs();
  sweep.total_points = static_cast<int32_t>(total);
  sweep.window = window;
  if (!plan->definition().SerializeToString(&sweep.definition)) {
    throw InternalError("sweep: its definition cannot be serialized");
  }
  // This replica's feeder waits until the first window is queued (this call's runs).
  std::unique_lock<std::mutex> no_round = m_.feeder_.HoldRounds();
  for (int attempt = 0;; ++attempt) {
    MBSTREAM_CHECK_MSG(attempt < 100, "no free sweep ids after 100 attempts");
    sweep.id = NewTimedId("s-");
    if (m_.store_->AddSweep(sweep)) break;
  }
  sweep.definition.clear();
  m_.feeder_.Remember(sweep.id, plan);
  spdlog::info("sweep {} stored: model {} '{}', {} points, window {}", sweep.id, model->info.id(),
               model->info.name(), total, window);
  Started started;
  started.id = sweep.id;
  started.total_points = sweep.total_points;
  started.paths = plan->paths();
  // The first window now (the queue may hold fewer: the feeder queues the rest as it frees).
  const int first = static_cast<int>(std::min<long>(std::min(window, m_.queue_.Room()), total));
  if (first > 0) started.runs = Feed(sweep, *plan, 0, first);
  no_round.unlock();
  for (const v1::RunInfo& run : started.runs)
    started.values.push_back(plan->Values(run.sweep_point()));
  m_.feeder_.Wake();
  return started;
}

std::vector<v1::RunInfo> RunSweeps::Feed(const StoredSweep& sweep, const SweepPlan& plan, int first,
                                         int count) {
  count = std::min(count, m_.queue_.Room());
  if (count <= 0) return {};
  std::shared_ptr<const CompiledModel> model = m_.FindModel(sweep.model_id);
  try {
    CheckFreeSpace(m_.free_space_source_, m_.limits_.min_free_bytes, m_.data_dir_);
  } catch (const RequestError& error) {
    spdlog::warn("sweep {}: not queueing more points: {}", sweep.id, error.what());
    return {};
  }
  // Each point's run: QUEUED with its config, or FAILED when the model refuses its spec.
  std::vector<v1::RunInfo> queued, failed;
  std::vector<RunConfig> configs;
  for (int k = first; k < first + count; ++k) {
    google::protobuf::RepeatedPtrField<v1::RunSpec> one;
    *one.Add() = plan.Spec(k, "sweep");
    std::vector<v1::RunInfo> info(1);
    v1::RunInfo* made = nullptr;
    try {
      configs.push_back(std::move(m_.PrepareRuns(*model, one, sweep.owner, info).front()));
      made = &queued.emplace_back(std::move(info.front()));
    } catch (const std::exception& error) {
      made = &failed.emplace_back();
      made->set_model_id(model->info.id());
      made->set_model_name(model->info.name());
      *made->mutable_spec() = one[0];
      made->set_state(v1::FAILED);
      made->set_message("point " + std::to_string(k) + " (" + plan.Label(k) + "): " + error.what());
      made->set_created_unix_ms(NowUnixMs());
      made->set_ended_unix_ms(made->created_unix_ms());
      made->set_owner(sweep.owner);
      for (const std::string& name : model->result_joint_names) made->add_joint_names(name);
    }
    made->set_sweep_id(sweep.id);
    made->set_sweep_point(k);
    made->set_sweep_points(sweep.total_points);
  }
  // Both kinds in point order, with the ids of this attempt: one store transaction.
  auto in_point_order = [&](const std::vector<v1::RunInfo>& with_ids) {
    std::vector<v1::RunInfo> all(with_ids.begin(), with_ids.end());
    for (v1::RunInfo info : failed) {
      info.set_id(m_.NewRunId());
      all.push_back(std::move(info));
    }
    std::sort(all.begin(), all.end(), [](const v1::RunInfo& a, const v1::RunInfo& b) {
      return a.sweep_point() < b.sweep_point();
    });
    return all;
  };
  std::vector<v1::RunInfo> stored;
  auto store_runs = [&](const std::vector<v1::RunInfo>& with_ids) {
    stored = in_point_order(with_ids);
    switch (m_.store_->AddSweepRuns(sweep.id, stored)) {
      case SweepFeed::kAdded:
        return true;
      case SweepFeed::kIdTaken:
        return false;
      case SweepFeed::kRefused:
        break;
    }
    throw SweepPointsRefused{};
  };
  try {
    if (queued.empty()) {
      for (int attempt = 0; !store_runs({}); ++attempt) {
        MBSTREAM_CHECK_MSG(attempt < 100, "no free run ids after 100 attempts");
      }
    } else {
      m_.queue_.Enqueue(
          queued,
          [&](const v1::RunInfo& info, size_t i) {
            return std::make_shared<Run>(info, configs[i], model, *m_.clock_, m_.ProbeOptions());
          },
          store_runs);
    }
  } catch (const SweepPointsRefused&) {
    return {};  // another replica queued them first, or the sweep was cancelled
  } catch (const RequestError& error) {
    // The queue is full or stopping: a later round tries again.
    spdlog::info("sweep {}: points {}..{} wait: {}", sweep.id, first, first + count - 1,
                 error.what());
    return {};
  }
  for (const v1::RunInfo& info : stored) {
    if (info.state() == v1::FAILED) {
      spdlog::warn("run {} of sweep {} FAILED: {}", info.id(), sweep.id, info.message());
    }
  }
  spdlog::info("sweep {}: points {}..{} queued", sweep.id, first, first + count - 1);
  return stored;
}

RunSweeps::View RunSweeps::Get(const std::string& sweep_id, int runs_from, int max_runs) const {
  View view;
  if (sweep_id.empty()) throw RequestError(RequestErrorKind::kNotFound, "give a sweep id (s-...)");
  view.stored = m_.store_->GetSweep(sweep_id, false);
  if (!view.stored) {  // started in slices by an older server: its runs are all there is
    view.runs = Runs(sweep_id);
    if (view.runs.empty()) {
      throw RequestError(RequestErrorKind::kNotFound,
                         "no sweep '" + sweep_id.substr(0, 80) +
                             "'; give the id `mbstream sweep` printed (s-...)");
    }
    for (const v1::RunInfo& run : view.runs) ++view.states[run.state()];
    return view;
  }
  view.states = m_.store_->CountSweepRuns(sweep_id);
  if (m_.replica_.private_store) {  // a run integrating here is still QUEUED in its row
    for (const v1::RunInfo& live : m_.queue_.SweepInfos(sweep_id)) {
      if (live.state() == v1::RUNNING && view.states[v1::QUEUED] > 0) {
        --view.states[v1::QUEUED];
        ++view.states[v1::RUNNING];
      }
    }
    if (view.states[v1::QUEUED] == 0) view.states.erase(v1::QUEUED);
  }
  constexpr int kMaxPage = 1000;
  max_runs = max_runs <= 0 ? kMaxPage : std::min(max_runs, kMaxPage);
  view.runs = m_.store_->ListSweepRuns(sweep_id, std::max(0, runs_from), max_runs);
  std::shared_ptr<const SweepPlan> plan;
  try {
    plan = m_.feeder_.Plan(*view.stored);
    view.paths = plan->paths();
  } catch (const InputError& error) {
    spdlog::error("sweep {}: {}", sweep_id, error.what());
  }
  for (v1::RunInfo& run : view.runs) {
    if (std::shared_ptr<Run> active = m_.FindActive(run.id()); active) {
      const bool cancelled = run.sweep_cancelled();
      run = active->Info();
      run.set_sweep_cancelled(run.sweep_cancelled() || cancelled);
    }
    if (plan && run.sweep_point() < plan->size()) {
      view.values.push_back(plan->Values(run.sweep_point()));
    } else {
      view.values.emplace_back();
    }
  }
  return view;
}

std::vector<v1::RunInfo> RunSweeps::Unfinished(const std::string& sweep_id) const {
  return m_.store_->ListSweepRuns(sweep_id, 0, 0, true);
}

std::vector<v1::RunInfo> RunSweeps::Runs(const std::string& sweep_id) const {
  std::vector<v1::RunInfo> runs;
  if (sweep_id.empty()) return runs;
  for (v1::RunInfo& stored : m_.store_->ListSweepRuns(sweep_id)) {
    // A run integrating here: its live info (the store's row is updated at its end only).
    if (std::shared_ptr<Run> run = m_.FindActive(stored.id()); run) {
      const bool cancelled = stored.sweep_cancelled();
      stored = run->Info();
      stored.set_sweep_cancelled(stored.sweep_cancelled() || cancelled);
    }
    runs.push_back(std::move(stored));
  }
  std::stable_sort(runs.begin(), runs.end(), [](const v1::RunInfo& a, const v1::RunInfo& b) {
    return a.sweep_point() < b.sweep_point();
  });
  return runs;
}

bool RunSweeps::Cancelled(const std::string& sweep_id) const {
  return !sweep_id.empty() && m_.store_->SweepCancelled(sweep_id);
}

int RunSweeps::MarkCancelled(const std::string& sweep_id) {
  if (sweep_id.empty()) return 0;
  return m_.store_->MarkSweepCancelled(sweep_id);
}

}  // namespace mbstream
