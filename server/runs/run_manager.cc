#include "server/runs/run_manager.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <optional>
#include <random>

#include "server/model/coordinate_names.h"
#include "server/runs/cluster_follow.h"
#include "server/runs/release_memory.h"
#include "server/runs/replica_id.h"
#include "server/runs/request_error.h"
#include "server/runs/run_budget_caps.h"
#include "server/runs/timed_id.h"
#include "server/runs/unix_time.h"
#include "server/sim/loop_run.h"
#include "server/sim/run_size.h"
#include "server/sim/run_validation.h"
#include "server/sim/simulate.h"
#include "server/spec/run_spec_json.h"
#include "server/store/frame_chunks.h"
#include "server/store/store.h"
#include "server/wire/stats_conversion.h"
#include "shared/common/check.h"

#ifndef MBSTREAM_VERSION
#define MBSTREAM_VERSION "unknown"
#endif

namespace mbstream {

namespace {

// `replica` with an id (a new one when none is given).
ReplicaOptions WithId(ReplicaOptions replica) {
  if (replica.id.empty()) replica.id = NewReplicaId();
  return replica;
}

}  // namespace

RunManager::RunManager(ModelRegistry* models, Store* store, const ServerLimits& limits,
                       RunClock* clock, ReplicaOptions replica)
    : models_(models),
      store_(store),
      limits_(limits),
      clock_(clock != nullptr ? clock : &SteadyRunClock()),
      replica_(WithId(std::move(replica))),
      recent_results_(static_cast<std::size_t>(std::max<int64_t>(limits_.recent_results_bytes, 0))),
      fan_out_(limits_.max_subscribers, limits_.subscriber_queue_frames),
      follower_replays_(store_, clock_),
      feeder_(
          store_,
          std::chrono::milliseconds(
              replica_.private_store
                  ? 1000
                  : std::max<int64_t>(50, static_cast<int64_t>(replica_.claim_poll_s * 1000))),
          [this](const StoredSweep& sweep, const SweepPlan& plan, int first, int count) {
            return !sweeps_.Feed(sweep, plan, first, count).empty();
          },
          [this] { pending_finals_.Retry(*store_); }),
      queue_(store_, replica_, limits_, QueueHooks()) {
  MBSTREAM_CHECK(models_ != nullptr && store_ != nullptr && limits_.workers > 0);
  feeder_.Start();
  if (!replica_.private_store) {
    cluster_follow_ = std::make_unique<ClusterFollow>(
        store_, replica_.id, std::chrono::duration<double>(replica_.claim_poll_s),
        [this] { return fan_out_.has_followers(); },
        [this](const v1::RunInfo& info) { fan_out_.AnnounceRemote(info.id()); });
  }
}

RunManager::~RunManager() { replica_control_.Shutdown("the server stopped"); }

std::string RunManager::NewRunId() const {
  // StartMany draws again on a collision (the store refuses a taken id, AddRuns).
  return NewTimedId("r-");
}

RunConfig RunManager::PrepareConfig(const CompiledModel& model, const v1::RunSpec& spec,
                                    std::vector<std::string>* warnings) const {
  RunConfig config =
      ToRunConfig(spec, SpecCoordinates{PositionNames(model.model), model.joint_names}, "spec");
  if (!spec.has_gravity()) config.gravity = model.model.gravity;  // an SDF world's <gravity>
  ValidateLoopRun(model.model, model.loops, config);  // the one validation; throws InputError
  CheckRunSize(config, spec.max_output_frames(),
               RunSizeLimits{limits_.max_duration_s, limits_.max_output_frames});
  if (spec.realtime() > 0.0 && config.duration / spec.realtime() > limits_.max_duration_s) {
    throw RequestError(RequestErrorKind::kResourceExhausted,
                       "spec.realtime " + std::to_string(spec.realtime()) + " paces " +
                           std::to_string(config.duration) + " s of simulated time over " +
                           std::to_string(config.duration / spec.realtime()) +
                           " s of wall time, more than this server's limit of " +
                           std::to_string(limits_.max_duration_s) +
                           " s; raise realtime or give 0 (unpaced)");
  }
  for (std::string& warning : PrepareRunBudget(model.model, limits_, &config)) {
    warnings->push_back(std::move(warning));
  }
  return config;
}

v1::RunInfo RunManager::Start(const std::string& model_ref, const v1::RunSpec& spec,
                              const std::string& owner) {
  google::protobuf::RepeatedPtrField<v1::RunSpec> one;
  *one.Add() = spec;
  return std::move(StartMany(model_ref, one, owner).front());
}

std::vector<v1::RunInfo> RunManager::StartMany(
    const std::string& model_ref, const google::protobuf::RepeatedPtrField<v1::RunSpec>& specs,
    const std::string& owner, const std::string& sweep_id, int first_point, int total_points) {
  std::shared_ptr<const CompiledModel> model = FindModel(model_ref);
  const int count = specs.size();
  if (count == 0) throw InputError("specs is empty; give at least one run spec");
  if (count > limits_.max_queued_runs) {
    throw RequestError(RequestErrorKind::kResourceExhausted,
                       std::to_string(count) +
                           " runs at once exceed this server's run queue; start them in "
                           "batches of at most " +
                           std::to_string(limits_.max_queued_runs));
  }
  // A disk nearly full refuses new runs before they fail on it (docs/reliability.md).
  CheckFreeSpace(free_space_source_, limits_.min_free_bytes, data_dir_);
  std::vector<v1::RunInfo> infos(count);
  const std::vector<RunConfig> configs = PrepareRuns(*model, specs, owner, infos);
  if (!sweep_id.empty()) {
    for (int i = 0; i < count; ++i) {
      infos[i].set_sweep_id(sweep_id);
      infos[i].set_sweep_point(first_point + i);
      infos[i].set_sweep_points(total_points);
    }
  }
  queue_.Enqueue(infos, [&](const v1::RunInfo& info, size_t i) {
    return std::make_shared<Run>(info, configs[i], model, *clock_, ProbeOptions());
  });
  for (const v1::RunInfo& info : infos) {
    spdlog::info("run {} queued: model {} '{}', {} s, {} frames", info.id(), model->info.id(),
                 model->info.name(), info.duration_s(), info.expected_frames());
  }
  return infos;
}

std::vector<RunConfig> RunManager::PrepareRuns(
    const CompiledModel& model, const google::protobuf::RepeatedPtrField<v1::RunSpec>& specs,
    const std::string& owner, std::vector<v1::RunInfo>& infos) {
  // Every spec checked before anything is queued; a batch's errors name the spec.
  const int count = specs.size();
  std::vector<RunConfig> configs;
  configs.reserve(count);
  for (int i = 0; i < count; ++i) {
    const v1::RunSpec& spec = specs[i];
    const std::string where = count > 1 ? "specs[" + std::to_string(i) + "]: " : "";
    std::vector<std::string> warnings;
    try {
      configs.push_back(PrepareConfig(model, spec, &warnings));
    } catch (const InputError& e) {
      if (where.empty()) throw;
      throw InputError(where + e.what());
    } catch (const RequestError& e) {
      if (where.empty()) throw;
      throw RequestError(e.kind(), where + e.what());
    }
    const RunConfig& config = configs.back();
    v1::RunInfo& info = infos[i];
    info.set_model_id(model.info.id());
    info.set_model_name(model.info.name());
    *info.mutable_spec() = spec;
    info.mutable_spec()->DiscardUnknownFields();  // kept in every RunInfo: only what we read
    info.set_state(v1::QUEUED);
    info.set_expected_frames(
        KeptFrameCount(config.keep, OutputFrameCount(config.duration, config.output_interval)));
    info.set_duration_s(config.duration);
    // Every joint of the model file: a closed loop's cut joints after the tree's.
    info.set_num_dofs(static_cast<int>(model.result_joint_names.size()));
    for (const std::string& name : model.result_joint_names) info.add_joint_names(name);
    if (model.model.has_quaternions()) {  // Frame.q then has nq values (run.proto)
      info.set_num_positions(model.model.nq());
      for (const std::string& name : PositionNames(model.model)) info.add_position_names(name);
    }
    info.set_created_unix_ms(NowUnixMs());
    info.set_mbstream_version(MBSTREAM_VERSION);
    info.set_owner(owner);
    for (const std::string& warning : warnings) info.add_warnings(warning);
  }
  return configs;
}

v1::RunInfo RunManager::Cancel(const std::string& run_id) {
  if (std::optional<v1::RunInfo> cancelled = queue_.Cancel(run_id)) {
    // A worker waiting for the run's controller looks at the cancel flag now.
    if (const std::shared_ptr<Run> run = FindActive(run_id); run && run->control()) {
      run->control()->Wake();
    }
    return *cancelled;
  }
  v1::RunInfo info = Get(run_id);
  if (!IsFinalState(info.state())) {
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       "run " + run_id + " is integrating on replica " + info.replica() + " (" +
                           info.replica_address() + "); cancel it there (mbstream --server " +
                           info.replica_address() + " cancel " + run_id + ")");
  }
  return info;
}

v1::RunInfo RunManager::Get(const std::string& run_id) const {
  if (std::shared_ptr<Run> run = FindActive(run_id)) return run->Info();
  if (v1::RunInfo info; recent_results_.GetInfo(run_id, info)) return info;  // ended here
  if (v1::RunInfo info; pending_finals_.Find(run_id, info)) return info;     // not stored yet
  std::optional<v1::RunInfo> stored = store_->GetRun(run_id);
  if (!stored) throw UnknownRunError(run_id);
  return *stored;
}

RunManager::RunPage RunManager::List(const std::string& model, int limit, int page_size,
                                     const std::string& page_token) const {
  constexpr int kDefaultPage = 100, kMaxPage = 1000;
  if (limit < 0 || page_size < 0) {
    throw InputError("ListRuns: limit and page_size must be >= 0 (0 = no limit / the default)");
  }
  // The token: "<last run id returned> <runs left of the limit, 0 = no limit>".
  std::string after;
  int64_t left = limit;
  if (!page_token.empty()) {
    const size_t space = page_token.find(' ');
    char* end = nullptr;
    left = space == std::string::npos ? -1 : std::strtoll(page_token.c_str() + space + 1, &end, 10);
    if (left < 0 || *end != '\0') {
      throw InputError(
          "ListRuns: page_token is not one this server gave; pass "
          "next_page_token unchanged, or none for the first page");
    }
    after = page_token.substr(0, space);
  }
  const int64_t size = std::min<int64_t>(
      {page_size > 0 ? page_size : kDefaultPage, kMaxPage, left > 0 ? left : kMaxPage});
  std::string model_id;
  if (!model.empty()) model_id = models_->Info(model).id();
  const std::vector<v1::RunInfo> runs = store_->ListRuns();
  auto it = runs.rbegin();
  if (!after.empty()) {
    it = std::find_if(runs.rbegin(), runs.rend(),
                      [&](const v1::RunInfo& r) { return r.id() == after; });
    if (it == runs.rend()) {
      throw InputError("ListRuns: page_token names run '" + after.substr(0, 64) +
                       "', which this server does not have; start again without a token");
    }
    ++it;
  }
  RunPage page;
  size_t bytes = 0;
  for (; it != runs.rend(); ++it) {
    if (!model_id.empty() && it->model_id() != model_id) continue;
    if (static_cast<int64_t>(page.runs.size()) == size) break;
    std::shared_ptr<Run> run = FindActive(it->id());
    v1::RunInfo info = run ? run->Info() : *it;
    if (!run) pending_finals_.Find(it->id(), info);  // ended, its row not written yet (full disk)
    if (info.ByteSizeLong() > kMaxPageBytes / 4) {   // stored by an older server: spec unbounded
      info.clear_spec();
      info.set_message(info.message() + " [spec omitted from the list: too large; GetRun has it]");
    }
    bytes += info.ByteSizeLong();
    if (bytes > kMaxPageBytes && !page.runs.empty()) break;
    page.runs.push_back(std::move(info));
  }
  const int64_t remaining = left > 0 ? left - static_cast<int64_t>(page.runs.size()) : 0;
  const bool more = std::any_of(it, runs.rend(), [&](const v1::RunInfo& r) {
    return model_id.empty() || r.model_id() == model_id;
  });
  if (more && !page.runs.empty() && (left == 0 || remaining > 0)) {
    page.next_page_token = page.runs.back().id() + " " + std::to_string(remaining);
  }
  return page;
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

ProbeRecorder::Options RunManager::ProbeOptions() const {
  ProbeRecorder::Options options;
  options.max_reports = limits_.max_probe_reports;
  options.interval = std::chrono::duration_cast<RunClock::TimePoint::duration>(
      std::chrono::duration<double>(std::max(limits_.frame_flush_s, 0.0)));
  return options;
}

}  // namespace mbstream
