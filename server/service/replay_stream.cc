// SendReplay and PlanReplay: a stored run streamed to one viewer at its original pace.
#include "server/service/replay_stream.h"

#include <algorithm>
#include <cmath>
#include <deque>

#include "server/runs/request_error.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kMaxSpeed = 1000.0;
constexpr size_t kMaxTagBytes = 128;
constexpr auto kPoll = std::chrono::milliseconds(100);  // checks for cancellation and stop
// With Replay.wait_for_probes, a viewer is sent at most this many frames ahead of its newest
// probe answer (well inside
// SentFrames' memory, so that no answer is refused as too old): an unpaced replay goes as
// fast as the viewer takes frames. A viewer that does not answer within kFirstAnswer of
// the start (a scene without probes; the scene is built meanwhile), or stops answering for
// kStall, is not waited for again.
constexpr size_t kMaxAhead = 1024;
constexpr auto kFirstAnswer = std::chrono::seconds(10);
constexpr auto kStall = std::chrono::seconds(2);

ReplayGridRun GridRun(const v1::RunInfo& info, ReplayCursor& frames) {
  ReplayGridRun run;
  run.id = info.id();
  run.frames = info.frames();
  run.joint_names.assign(info.joint_names().begin(), info.joint_names().end());
  if (run.frames > 1) run.interval_s = frames.At(1).t_s() - frames.At(0).t_s();
  return run;
}

// The ended run `run_id` (ResultInfo's errors), with at least one stored frame.
v1::RunInfo EndedRun(RunManager& runs, const std::string& run_id, const char* what) {
  if (runs.replays().IsActive(run_id)) {
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       std::string(what) + " run " + run_id +
                           " has not ended: only a stored run can be replayed from another "
                           "frame, paused or compared; watch it live (no replay options) or "
                           "wait for it to end");
  }
  v1::RunInfo info = runs.results().Info(run_id);
  if (info.frames() < 1) {
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       std::string(what) + " run " + run_id + " ended " +
                           v1::RunState_Name(info.state()) +
                           " before its first frame: there is nothing to replay");
  }
  return info;
}

}  // namespace

std::string CheckReplaySpeed(double speed) {
  if (std::isfinite(speed) && speed >= 0.0 && speed <= kMaxSpeed) return "";
  return "speed " + std::to_string(speed) + " is out of range; give 0 (unpaced) or a speed up to " +
         std::to_string(static_cast<int>(kMaxSpeed)) + " (1 = real time)";
}

std::optional<ReplayPlan> PlanReplay(RunManager& runs, const v1::SubscribeRequest::Start& start) {
  const v1::Replay& options = start.replay();
  if (const std::string bad = CheckReplaySpeed(options.speed()); !bad.empty()) {
    throw InputError("Subscribe: start.replay." + bad);
  }
  if (options.from_seq() < 0) {
    throw InputError("Subscribe: start.replay.from_seq is " + std::to_string(options.from_seq()) +
                     "; give a frame number from 0");
  }
  if (options.viewer().size() > kMaxTagBytes || options.scene().size() > kMaxTagBytes) {
    throw InputError("Subscribe: start.replay.viewer and .scene take at most " +
                     std::to_string(kMaxTagBytes) + " bytes each");
  }
  const bool live_compatible =
      options.from_seq() == 0 && options.compare_run_id().empty() && !options.paused();
  if (live_compatible && runs.replays().IsActive(start.run_id())) return std::nullopt;

  ReplayPlan plan;
  plan.options = options;
  plan.run = EndedRun(runs, start.run_id(), "the");
  plan.run_frames = runs.replays().Open(plan.run);
  if (options.from_seq() >= plan.run.frames()) {
    throw InputError("Subscribe: start.replay.from_seq is " + std::to_string(options.from_seq()) +
                     " but run " + plan.run.id() + " has " + std::to_string(plan.run.frames()) +
                     " frames; give 0 to " + std::to_string(plan.run.frames() - 1));
  }
  const ReplayGridRun run = GridRun(plan.run, *plan.run_frames);
  if (options.compare_run_id().empty()) {
    plan.grid = SingleRunGrid(run);
  } else {
    plan.ghost = EndedRun(runs, options.compare_run_id(), "the compared");
    plan.ghost_frames = runs.replays().Open(*plan.ghost);
    plan.grid = AlignReplayGrids(run, GridRun(*plan.ghost, *plan.ghost_frames));
    // A run whose duration is no whole number of intervals ends with an extra frame at its
    // end time, off the grid: leave it out.
    const int64_t last = plan.grid.frames - 1;
    const double t_run = plan.run_frames->At(last * plan.grid.stride).t_s();
    const double t_ghost = plan.ghost_frames->At(last * plan.grid.ghost_stride).t_s();
    if (last > 0 && std::abs(t_run - t_ghost) > 1e-9 * std::max(1.0, std::abs(t_run))) {
      plan.grid.frames = last;
    }
  }
  plan.start_step = std::min(options.from_seq() / plan.grid.stride, plan.grid.frames - 1);
  return plan;
}

namespace {

// The replay's position and pace.
struct Player {
  ReplayPlan* plan = nullptr;
  int64_t step = 0;        // the grid step sent next
  int64_t last_sent = -1;  // the grid step sent last
  bool paused = false;
  bool send_one = false;  // send `step` even though paused (a seek or step)
  bool state_after_send = false;
  double speed = 1.0;
  Clock::time_point anchor_wall;
  double anchor_t = 0.0;  // s, simulated time shown at anchor_wall

  const v1::Frame& Frame(int64_t k) { return plan->run_frames->At(k * plan->grid.stride); }
  const v1::Frame& Ghost(int64_t k) { return plan->ghost_frames->At(k * plan->grid.ghost_stride); }
  void Anchor() {
    anchor_wall = Clock::now();
    anchor_t = step < plan->grid.frames ? Frame(step).t_s() : 0.0;
  }
  Clock::time_point Due(int64_t k) {
    if (speed <= 0.0) return anchor_wall;
    return anchor_wall + std::chrono::duration_cast<Clock::duration>(
                             std::chrono::duration<double>((Frame(k).t_s() - anchor_t) / speed));
  }
  void FillState(v1::ReplayState* state, const std::string& set_id) const {
    state->Clear();
    state->set_run_id(plan->run.id());
    state->set_paused(paused);
    state->set_seq(last_sent < 0 ? -1 : last_sent * plan->grid.stride);
    state->set_frames(plan->run.frames());
    state->set_stride(plan->grid.stride);
    state->set_speed(speed);
    if (plan->ghost) state->set_compare_run_id(plan->ghost->id());
    state->set_ghost_stride(plan->grid.ghost_stride);
    state->set_grid_frames(plan->grid.frames);
    state->set_probe_set(set_id);
  }
  // Applies `control`; returns "" or why it could not be applied. Whether a state must be
  // sent now (else after the next frame) goes to `state_now`.
  std::string Apply(const v1::ReplayControl& control, bool* state_now) {
    *state_now = true;
    switch (control.action_case()) {
      case v1::ReplayControl::kPause:
        paused = true;
        return "";
      case v1::ReplayControl::kResume:
        paused = false;
        if (step >= plan->grid.frames) step = 0;
        Anchor();
        return "";
      case v1::ReplayControl::kSpeed:
        if (std::string bad = CheckReplaySpeed(control.speed()); !bad.empty()) return bad;
        speed = control.speed();
        Anchor();
        return "";
      case v1::ReplayControl::kSeekSeq: {
        const int64_t seq = control.seek_seq();
        if (seq < 0 || seq >= plan->run.frames()) {
          return "seek_seq " + std::to_string(seq) + " is out of range; give 0 to " +
                 std::to_string(plan->run.frames() - 1);
        }
        step = std::min(seq / plan->grid.stride, plan->grid.frames - 1);
        break;
      }
      case v1::ReplayControl::kStep:
        paused = true;
        step = std::clamp<int64_t>((last_sent >= 0 ? last_sent : step) + control.step(), 0,
                                   plan->grid.frames - 1);
        break;
      default:
        return "an empty control; set one of pause, resume, seek_seq, step, speed";
    }
    send_one = true;
    state_after_send = true;
    *state_now = false;
    Anchor();
    return "";
  }
};

}  // namespace

namespace {

// Sends run_started, replay_state, the frames paced by their simulated times (and controls
// as they come), then run_ended (unless looping). Ends OK when the replay ended or the viewer
// said goodbye, UNAVAILABLE when the server stops (the call: CANCELLED when the viewer went
// away). Each Step sends what is due and asks to be woken for what comes next.
class ReplaySender final : public SubscribeSender {
 public:
  ReplaySender(ReplayPlan plan, int max_batch, bool contacts)
      : plan_(std::move(plan)), max_batch_(max_batch), contacts_(contacts) {
    player_.plan = &plan_;
    player_.step = plan_.start_step;
    player_.paused = plan_.options.paused();
    player_.send_one = player_.paused;
    player_.speed = plan_.options.speed();
    gate_ = plan_.options.wait_for_probes();
  }

  void Step(SubscribeCall& call) override {
    if (!started_) {
      SendStart(call);
      return;
    }
    ReplayInbox& inbox = *call.inbox();
    inbox.FlushIfDue();  // the viewer's reports, when their interval has passed
    if (call.stopping()) {
      const std::string reason = "the server is shutting down; reconnect later";
      v1::SubscribeEvent closing;
      closing.set_closing(reason);
      call.Enqueue(std::move(closing));
      call.Conclude(grpc::Status(grpc::StatusCode::UNAVAILABLE, reason));
      return;
    }
    if (call.reader_done()) {  // the viewer said goodbye
      call.Conclude(grpc::Status::OK);
      return;
    }
    for (v1::ReplayControl control; inbox.NextControl(Clock::now(), &control);) {
      bool state_now = true;
      const std::string error = player_.Apply(control, &state_now);
      if (state_now) SendState(call, error);
    }
    if (player_.paused && !player_.send_one) {
      call.WakeAt(Clock::now() + kPoll);  // or at the next control
      return;
    }
    if (player_.step >= plan_.grid.frames) {
      if (!plan_.options.loop()) {
        v1::SubscribeEvent ended;
        *ended.mutable_run_ended() = plan_.run;
        call.Enqueue(std::move(ended));
        call.Conclude(grpc::Status::OK);
        return;
      }
      player_.step = 0;
      player_.Anchor();
    }
    const Clock::time_point due = player_.Due(player_.step);
    if (!player_.send_one && WindowFull(inbox)) {
      call.WakeAt(Clock::now() + std::chrono::milliseconds(10));
      return;
    }
    if (!player_.send_one && Clock::now() < due) {
      call.WakeAt(std::min(due, Clock::now() + kPoll));
      return;
    }
    SendFrames(call);
  }

 private:
  void SendStart(SubscribeCall& call) {
    started_ = true;
    v1::SubscribeEvent event;
    auto* started = event.mutable_run_started();
    *started->mutable_run() = plan_.run;
    ModelRegistry& models = *call.deps().models;
    *started->mutable_model() = models.Info(plan_.run.model_id());
    *started->mutable_bundle() = models.Bundle(started->model().id());
    call.Enqueue(std::move(event));
    player_.Anchor();
    last_answer_ = Clock::now();
    SendState(call, "");
  }

  void SendState(SubscribeCall& call, const std::string& error) {
    v1::SubscribeEvent event;
    player_.FillState(event.mutable_replay_state(), call.inbox()->set().id());
    event.mutable_replay_state()->set_error(error);
    call.Enqueue(std::move(event));
  }

  // Whether the viewer is kMaxAhead frames behind in its probe answers (wait_for_probes).
  bool WindowFull(const ReplayInbox& inbox) {
    if (!gate_) return false;
    const int64_t answered = inbox.answered_seq();
    while (answered != last_answered_ && !ahead_.empty()) {
      const int64_t seq = ahead_.front();
      ahead_.pop_front();
      if (seq == answered) {
        last_answer_ = Clock::now();
        last_answered_ = answered;
        break;
      }
    }
    if (ahead_.size() < kMaxAhead) return false;
    if (Clock::now() - last_answer_ > (answered < 0 ? kFirstAnswer : kStall)) {
      gate_ = false;  // not waited for again: flow control alone
      ahead_.clear();
      return false;
    }
    return true;
  }

  void SendFrames(SubscribeCall& call) {
    v1::SubscribeEvent event;
    v1::FrameBatch* batch = event.mutable_frames();
    batch->set_run_id(plan_.run.id());
    const SentFrames::Clock::time_point now = SentFrames::Clock::now();
    do {
      const v1::Frame& frame = player_.Frame(player_.step);
      v1::Frame* sent = batch->add_frames();
      *sent = frame;
      if (!contacts_) sent->clear_contacts();
      call.sent().Record(plan_.run.id(), frame.seq(), frame.t_s(), now);
      if (plan_.ghost) *batch->add_ghost_frames() = player_.Ghost(player_.step);
      if (gate_) ahead_.push_back(frame.seq());
      player_.last_sent = player_.step++;
    } while (!player_.send_one && batch->frames_size() < max_batch_ &&
             player_.step < plan_.grid.frames && player_.Due(player_.step) <= Clock::now() &&
             ahead_.size() < kMaxAhead);
    player_.send_one = false;
    call.Enqueue(std::move(event));
    if (player_.state_after_send) {
      player_.state_after_send = false;
      SendState(call, "");
    }
  }

  ReplayPlan plan_;
  const int max_batch_;
  const bool contacts_;
  Player player_;
  bool started_ = false;
  // The frames sent and not yet answered, oldest first, while the viewer answers probes.
  std::deque<int64_t> ahead_;
  Clock::time_point last_answer_;
  int64_t last_answered_ = -1;  // the answer `ahead_` was last trimmed to
  // False without wait_for_probes, or once the viewer was not waited for: flow control alone.
  bool gate_ = false;
};

}  // namespace

std::unique_ptr<SubscribeSender> NewReplaySender(ReplayPlan plan, int max_batch, bool contacts) {
  return std::make_unique<ReplaySender>(std::move(plan), max_batch, contacts);
}

}  // namespace mbstream
