// RunManager's worker side (RunQueue's hooks): executing one claimed run and storing it.
#include <spdlog/spdlog.h>

#include <chrono>

#include "server/engine/engine.h"
#include "server/runs/run_manager.h"
#include "server/runs/unix_time.h"
#include "server/store/frame_chunks.h"
#include "server/store/store.h"
#include "server/wire/frame_conversion.h"
#include "server/wire/stats_conversion.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// Converts each frame to its wire form, paces it (realtime factor), hands it to the run's
// spool (which stores it with the next chunk, full or due: `flush_s` of the run's clock
// after the last, while `holder` holds the run's lease) and publishes it; then stores the
// viewers' probe reports when a batch of them is due (the run's ProbeRecorder). A store
// failure or a lost lease stops the run. One message is filled again for
// every frame (Run::Publish hands its storage back): no allocation per frame while nobody
// subscribes.
class PublishingSink : public FrameSink {
 public:
  PublishingSink(Run* run, Store* store, RunClock* clock, double flush_s, std::string holder)
      : run_(run), store_(store), clock_(clock), start_(clock->Now()) {
    run_->spool().FlushEvery(*clock_,
                             std::chrono::duration_cast<RunClock::TimePoint::duration>(
                                 std::chrono::duration<double>(flush_s)),
                             start_);
    run_->spool().WriteAs(std::move(holder));
  }

  bool KeepsFrames() const override { return true; }  // the spool stores them

  void OnFrame(const RunResult& result, int frame) override {
    if (seq_ == 0) {
      run_->UpdateInfo([&](v1::RunInfo& info) {
        info.set_has_torques(result.has_torques);
        info.set_has_energy(result.has_energy);
      });
    }
    FrameToProto(result, frame, &message_);
    message_.set_seq(seq_++);  // the kept frames' count (RunConfig::keep): consecutive
    Pace(result.t[frame]);
    run_->spool().Add(message_, *store_);
    run_->Publish(&message_);
    ProbeRecorder& probes = run_->probes();
    probes.FlushIfDue();
    if (!run_->spool().error().empty() || !probes.error().empty()) run_->cancel = true;
    if (run_->spool().lease_lost() ||
        probes.lease_lost()) {  // another replica has the run: it writes from now on
      run_->lease_lost = true;
      run_->cancel = true;
    }
  }

 private:
  // Realtime factor r > 0: frame at simulated time t goes out at wall time start + t / r.
  void Pace(double t) {
    const double realtime = run_->realtime();
    if (realtime <= 0.0) return;
    clock_->WaitUntil(start_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                   std::chrono::duration<double>(t / realtime)),
                      run_->cancel);
  }

  Run* run_;
  Store* store_;
  RunClock* clock_;
  RunClock::TimePoint start_;
  int64_t seq_ = 0;    // frames handed on so far
  v1::Frame message_;  // the frame being converted; the previous one's storage, after the first
};

}  // namespace

RunQueue::Hooks RunManager::QueueHooks() {
  RunQueue::Hooks hooks;
  hooks.new_run_id = [this] { return run_id_source_ ? run_id_source_() : NewRunId(); };
  hooks.prepare = [this](const v1::RunInfo& info) { return RunOf(info); };
  hooks.execute = [this](const std::shared_ptr<Run>& run) { RunClaimed(run); };
  hooks.state_changed = [this] { NoteStateChange(); };
  return hooks;
}

void RunManager::RunClaimed(const std::shared_ptr<Run>& run) {
  Outcome outcome;
  try {
    outcome = Execute(run);
  } catch (const InputError& error) {  // ValidateRun should have refused it
    spdlog::error("run {}: invalid input found only by the worker: {}", run->id(), error.what());
    outcome.state = v1::FAILED;
    outcome.message = error.what();
  } catch (const std::exception& error) {
    spdlog::error("run {}: {}", run->id(), error.what());
    outcome.state = v1::FAILED;
    outcome.message = std::string("internal error: ") + error.what();
  }
  Finish(run, outcome);
}

RunManager::Outcome RunManager::Execute(const std::shared_ptr<Run>& run) {
  Outcome outcome;
  if (run->cancel) {  // cancelled or interrupted while queued
    outcome.state = run->interrupted ? v1::INTERRUPTED : v1::CANCELLED;
    outcome.message = run->interrupted
                          ? queue_.stop_reason().value_or("") + " before this run started"
                          : "cancelled before it started";
    return outcome;
  }
  {
    // One step with AttachFollow (FanOut): each follower gets this run exactly once.
    fan_out_.AnnounceStart(
        *run, [&] { run->UpdateInfo([](v1::RunInfo& info) { info.set_state(v1::RUNNING); }); });
  }
  NoteStateChange();
  // Stored RUNNING already by the claim (RunQueue::ClaimNext; still QUEUED with a private store):
  // the row is written again when it ends.
  spdlog::info("run {} started", run->id());

  const std::string holder = replica_.private_store ? std::string() : LeaseHolder(run->Info());
  // Probe reports are stored as they come, each batch while `holder` still holds the lease
  // (checked by a renewal in its own transaction, before the batch's).
  run->probes().Open([this, id = run->id(), holder](const std::vector<v1::ProbeReport>& batch) {
    if (!holder.empty() && !store_->RenewLease(id, holder, queue_.NewLease().expires_unix_ms)) {
      return false;
    }
    store_->AddProbes(batch);
    return true;
  });
  PublishingSink sink(run.get(), store_, clock_, limits_.frame_flush_s, holder);
  const CompiledModel& model = run->model();
  const RunResult result =
      Simulate(model.model, model.loops, run->config(), &sink, &run->cancel, run->control().get());
  const RunStats& stats = result.stats;
  outcome.state = RunStateFromStatus(stats.status);
  outcome.message = stats.message;
  if (outcome.state == v1::CANCELLED && run->interrupted) {
    outcome.state = v1::INTERRUPTED;
    outcome.message = queue_.stop_reason().value_or("") +
                      " during this run; the frames up to t = " + std::to_string(stats.t_reached) +
                      " s are kept";
  }
  outcome.stats = StatsToProto(stats);
  return outcome;
}

v1::RunInfo RunManager::FinalInfo(Run& run, const Outcome& outcome) {
  v1::RunInfo info = run.Info();
  info.set_state(outcome.state);
  info.set_message(outcome.message);
  *info.mutable_stats() = outcome.stats;
  info.set_ended_unix_ms(NowUnixMs());
  run.probes().Close();  // later reports are refused
  if (const std::string& error = run.spool().error(); !error.empty()) {
    info.set_state(v1::FAILED);
    info.set_message("the frames could not be stored (" + error +
                     "); the run was stopped, the frames stored before are kept");
  } else if (const std::string probe_error = run.probes().error(); !probe_error.empty()) {
    info.set_state(v1::FAILED);
    info.set_message("the probe reports could not be stored (" + probe_error +
                     "); the run was stopped, the frames and reports stored before are kept");
  }
  if (run.interrupted && !replica_.private_store) {  // drained or stopped: hand it back
    ApplyHandBack(info, info.ended_unix_ms(), outcome.message);
  }
  return info;
}

void RunManager::StoreFinal(Run& run, v1::RunInfo& info) {
  // The frames are in the store already but for the spool's last chunk, written together
  // with the final info; the probe reports but for the recorder's last batch, stored just
  // before. Nothing is stored once another replica took the run over.
  // A private store's runs hold no lease (RunQueue::ClaimPrivate): stored unconditionally.
  const std::string holder = replica_.private_store ? std::string() : LeaseHolder(run.Info());
  try {
    // The lease is checked in the transaction that stores the result; the probe recorder's
    // last batch, stored before it, checks it with a renewal of its own (Execute).
    if (run.lease_lost || run.probes().lease_lost()) {
      run.lease_lost = true;
    } else if (info.state() == v1::QUEUED) {  // its reports not stored yet are dropped
      if (!store_->PutRunIfHeld(info, holder)) run.lease_lost = true;
      spdlog::info("run {} handed back to the queue: {}", run.id(), info.message());
    } else if (!run.probes().Flush()) {
      run.lease_lost = true;
    } else {
      if (!run.spool().Finish(info, *store_, holder)) {
        run.lease_lost = true;
      } else if (std::string whole = run.spool().TakeWholeResult();
                 (!whole.empty() || info.frames() == 0) &&
                 info.state() != v1::INTERRUPTED) {  // final for good
        // Before anyone sees the run ended; a run without frames (a sweep's, keeping the
        // summary) too: its GetResult then reads its row once, not twice.
        recent_results_.Put(info, std::move(whole));
      }
    }
  } catch (const std::exception& error) {
    spdlog::error("run {}: storing the result failed: {}", run.id(), error.what());
    info.set_state(v1::FAILED);
    info.set_message(std::string("the result could not be stored: ") + error.what());
    try {
      store_->PutRun(info);  // at least the final state, if the store takes that
    } catch (const std::exception& again) {
      // Shown as it is meanwhile (Get, RunResults::Info), and written once the store takes it.
      spdlog::error(
          "run {}: storing its final state failed too ({}); it is written again "
          "until the store takes it",
          run.id(), again.what());
      pending_finals_.Add(info);
    }
  }
  if (run.lease_lost) {  // show what the store holds, as the replica that took it over wrote
    spdlog::warn("run {}: replica {} lost its lease; nothing more stored here", run.id(),
                 replica_.id);
    try {
      if (std::optional<v1::RunInfo> stored = store_->GetRun(run.id())) info = *stored;
    } catch (const std::exception& error) {
      spdlog::error("run {}: reading it back failed: {}", run.id(), error.what());
    }
  }
}

void RunManager::Finish(const std::shared_ptr<Run>& run, const Outcome& outcome) {
  if (const std::shared_ptr<const v1::Frame> last = run->latest_frame();
      last != nullptr && !run->interrupted && !run->lease_lost) {
    run->WaitForProbes(last->seq(), std::chrono::duration<double>(limits_.probe_grace_s));
  }
  // Store first, then show the final state: whoever sees a run ended can fetch its result.
  v1::RunInfo info = FinalInfo(*run, outcome);
  StoreFinal(*run, info);
  run->UpdateInfo([&](v1::RunInfo& live) { live = info; });
  queue_.Release(run);
  run->End();
  if (run->control()) run->control()->Close();  // its stream sends `ended`
  NoteStateChange();
  info = run->Info();
  spdlog::info("run {} {}: {} frames to t = {} s, {} steps, cpu {:.3f} ms, wall {:.3f} ms{}{}",
               run->id(), v1::RunState_Name(info.state()), info.frames(),
               info.stats().t_reached_s(), info.stats().steps(), 1e3 * info.stats().cpu_s(),
               1e3 * info.stats().wall_s(), info.message().empty() ? "" : ": ", info.message());
  // After a burst only: at least a stored chunk's worth of joint values (4,096 frames of a
  // 6-joint arm, about 1 MB; fewer frames of a bigger model). Trimming the heap and SQLite's
  // page cache after every short run cost more than the run itself (madvise, page faults
  // refilling the pages, the cache read back from disk; docs/performance.md, "Many runs at
  // once").
  const int64_t joint_values = info.frames() * std::max(1, run->model().model.num_dofs());
  if (joint_values >= static_cast<int64_t>(kFramesPerChunk) * 6) results_.ReleaseMemory();
}

}  // namespace mbstream
