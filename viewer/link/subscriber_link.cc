#include "viewer/link/subscriber_link.h"

#include <grpcpp/grpcpp.h>
#include <spdlog/spdlog.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "shared/common/check.h"
#include "shared/net/tls_files.h"

namespace mbstream::viewer {

namespace {

using Clock = std::chrono::steady_clock;
using SubscribeStream = grpc::ClientReaderWriter<v1::SubscribeRequest, v1::SubscribeEvent>;

// Who answers a replay's probes, for its probe set: "host:pid".
std::string ViewerTag() {
  char host[256] = {};
  if (gethostname(host, sizeof(host) - 1) != 0) host[0] = '\0';
  return std::string(host) + ":" + std::to_string(getpid());
}

void SetReplay(const ReplayOptions& options, v1::Replay* replay) {
  replay->set_speed(options.speed);
  replay->set_loop(options.loop);
  replay->set_from_seq(options.from_seq);
  replay->set_paused(options.paused);
  replay->set_compare_run_id(options.compare_run_id);
  replay->set_viewer(ViewerTag());
  replay->set_scene(options.scene_tag.substr(0, 128));
  replay->set_wait_for_probes(true);  // every frame is answered (a scene has its probes)
}

double Distance(const v1::Vector3& a, const v1::Vector3& b) {
  const double dx = a.x() - b.x(), dy = a.y() - b.y(), dz = a.z() - b.z();
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

// A frame's contacts as the layer draws them: each point, and the force on the pair's first
// body (normal force along the normal, plus friction), into `out` (its storage reused).
void ContactMarks(const v1::Frame& frame, std::vector<ContactMark>* out) {
  out->resize(frame.contacts_size());
  for (int i = 0; i < frame.contacts_size(); ++i) {
    const v1::FrameContact& c = frame.contacts(i);
    ContactMark& m = (*out)[i];
    m.point = {c.point_m().x(), c.point_m().y(), c.point_m().z()};
    m.force = c.normal_force_n() * Eigen::Vector3d(c.normal().x(), c.normal().y(), c.normal().z()) +
              Eigen::Vector3d(c.friction_force_n().x(), c.friction_force_n().y(),
                              c.friction_force_n().z());
  }
}

bool IsFatal(grpc::StatusCode code) {
  return code == grpc::StatusCode::NOT_FOUND || code == grpc::StatusCode::INVALID_ARGUMENT ||
         code == grpc::StatusCode::UNAUTHENTICATED || code == grpc::StatusCode::PERMISSION_DENIED;
}

}  // namespace

SubscriberLink::SubscriberLink(LinkOptions options, RunSceneSource scenes, SceneSlot* slot,
                               LinkStatus* status)
    : options_(std::move(options)), scenes_(std::move(scenes)), slot_(slot), status_(status) {}

void SubscriberLink::Stop() {
  stop_ = true;
  std::lock_guard<std::mutex> lock(context_mutex_);
  if (context_) static_cast<grpc::ClientContext*>(context_)->TryCancel();
}

bool SubscriberLink::SendControl(const v1::ReplayControl& control) {
  v1::SubscribeRequest request;
  *request.mutable_control() = control;
  return Write(request);
}

int SubscriberLink::Run() {
  status_->SetServer(options_.server);
  int runs_ended = 0;
  double backoff_s = 0.25;
  while (!stop_) {
    status_->SetState("connecting");
    const Clock::time_point attempt = Clock::now();
    StreamEnd end;
    try {
      end = Stream(&runs_ended);
    } catch (const net::SecurityConfigError& e) {
      spdlog::error("{}", e.what());
      return 1;
    }
    if (end == StreamEnd::kDone) return 0;
    if (end == StreamEnd::kFatal) return 1;
    if (stop_) break;
    if (Clock::now() - attempt > std::chrono::seconds(5)) backoff_s = 0.25;  // it was up
    spdlog::warn("the server {} is not reachable; retrying in {:.2f} s", options_.server,
                 backoff_s);
    for (const auto until = Clock::now() + std::chrono::duration<double>(backoff_s);
         Clock::now() < until && !stop_;) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    backoff_s = std::min(backoff_s * 2, 8.0);
  }
  return 0;
}

struct SubscriberLink::StreamState {
  std::string run_id;
  bool showing = false;        // the current run has a scene
  bool done = false;           // stop reading: the run (or the last run asked for) ended
  bool fatal = false;          // ... and exit with an error
  bool broken = false;         // a write failed: the stream is gone
  v1::SubscribeRequest reply;  // reused for every probe report
  std::vector<ProbeReport> probes;
  std::vector<double> q, ghost_q;
  std::vector<ContactMark> contacts;  // the frame's, reused
  // The model's position coordinates (ModelInfo.positions, else dofs): a frame's values beyond
  // them are the columns of the joints cut to close loops (the server's results order: the tree's
  // joints, then the cut joints'), which pose nothing.
  int model_dofs = 0;
  bool probes_logged = false;  // "first probe reports" said for this run
};

bool SubscriberLink::Write(const v1::SubscribeRequest& request) {
  std::lock_guard<std::mutex> lock(write_mutex_);
  return writer_ != nullptr && static_cast<SubscribeStream*>(writer_)->Write(request);
}

SubscriberLink::StreamEnd SubscriberLink::Stream(int* runs_ended) {
  auto stub = v1::Simulation::NewStub(net::MakeChannel(options_.server, options_.security));
  grpc::ClientContext context;
  {
    std::lock_guard<std::mutex> lock(context_mutex_);
    if (stop_) return StreamEnd::kDone;  // Stop() came first: it cancels no later stream
    context_ = &context;
  }
  struct ClearContext {  // before `context` goes (declared after it)
    SubscriberLink* link;
    ~ClearContext() {
      std::lock_guard<std::mutex> lock(link->context_mutex_);
      link->context_ = nullptr;
    }
  } clear{this};
  auto stream = stub->Subscribe(&context);
  stream->Write(StartRequest());
  {
    std::lock_guard<std::mutex> lock(write_mutex_);
    writer_ = stream.get();
  }
  status_->SetState("waiting");

  v1::SubscribeEvent event;
  StreamState state;
  bool closing = false;
  while (!state.done && !state.broken && !closing && stream->Read(&event)) {
    closing = !Dispatch(event, runs_ended, &state);
  }
  // Half-close: the server ends the stream (also a follow stream) once it has read our last
  // probe reports; drain what it still sends.
  {
    std::lock_guard<std::mutex> lock(write_mutex_);
    writer_ = nullptr;
    stream->WritesDone();
  }
  if (state.done) {
    while (stream->Read(&event)) {
    }
    stream->Finish();
    return state.fatal ? StreamEnd::kFatal : StreamEnd::kDone;
  }
  const grpc::Status status = stream->Finish();
  if (stop_) return StreamEnd::kDone;
  if (IsFatal(status.error_code())) {
    spdlog::error("the server refused the subscription: {}", status.error_message());
    return StreamEnd::kFatal;
  }
  spdlog::warn("the stream ended: {} ({})", status.error_message(),
               static_cast<int>(status.error_code()));
  return StreamEnd::kRetry;
}

v1::SubscribeRequest SubscriberLink::StartRequest() const {
  v1::SubscribeRequest start;
  if (options_.follow) {
    start.mutable_start()->set_follow(true);
  } else {
    start.mutable_start()->set_run_id(options_.run_id);
    SetReplay(options_.replay, start.mutable_start()->mutable_replay());
  }
  start.mutable_start()->set_max_batch(options_.max_batch);
  start.mutable_start()->set_contacts(options_.contacts);
  return start;
}

bool SubscriberLink::Dispatch(const v1::SubscribeEvent& event, int* runs_ended,
                              StreamState* state) {
  switch (event.event_case()) {
    case v1::SubscribeEvent::kSubscribed:
      spdlog::info("subscribed to {}: {}", options_.server, event.subscribed());
      break;
    case v1::SubscribeEvent::kClosing:
      // The caller half-closes; the stream ends UNAVAILABLE and the link reconnects.
      spdlog::warn("{}: {}", options_.server, event.closing());
      return false;
    case v1::SubscribeEvent::kRunStarted:
      OnRunStarted(event.run_started(), state);
      break;
    case v1::SubscribeEvent::kReplayState:
      OnReplayState(event.replay_state(), *state);
      break;
    case v1::SubscribeEvent::kFrames:
      OnFrames(event.frames(), state);
      break;
    case v1::SubscribeEvent::kRunEnded:
      OnRunEnded(event.run_ended(), runs_ended, state);
      break;
    case v1::SubscribeEvent::EVENT_NOT_SET:
      break;
  }
  return true;
}

std::string SubscriberLink::ShowRun(const v1::SubscribeEvent::RunStarted& started) {
  SceneDescription scene;
  try {
    scene = SceneForModel(started.model(), started.bundle(), scenes_);
  } catch (const std::exception& e) {  // InputError, or a mesh file that cannot be read
    return e.what();
  }
  for (const std::string& warning : scene.warnings) spdlog::warn("{}", warning);
  const std::string title = scene.title;
  if (std::string error = slot_->Replace(std::move(scene)); !error.empty()) return error;
  const v1::RunInfo& run = started.run();
  const v1::ModelInfo& model = started.model();  // ViewerStatus.dofs: q's length
  status_->StartRun(run.id(), model.id(), title,
                    model.positions() > 0 ? model.positions() : model.dofs());
  status_->SetMethod(
      run.stats().formulation().empty() ? run.spec().formulation() : run.stats().formulation(),
      run.stats().method().empty() ? run.spec().method() : run.stats().method());
  spdlog::info("run {} of model '{}' ({}): showing scene '{}'", run.id(), started.model().name(),
               started.model().id(), title);
  return "";
}

void SubscriberLink::OnRunStarted(const v1::SubscribeEvent::RunStarted& started,
                                  StreamState* state) {
  state->run_id = started.run().id();
  // With free bodies q has `positions` values (a free joint's 7), more than its dofs.
  state->model_dofs =
      started.model().positions() > 0 ? started.model().positions() : started.model().dofs();
  state->probes_logged = false;
  const std::string error = ShowRun(started);
  state->showing = error.empty();
  if (state->showing) return;
  spdlog::error("run {}: {}", state->run_id, error);
  if (!options_.follow) {  // --run: the one run cannot be shown
    state->fatal = true;
    state->done = true;
  }
}

void SubscriberLink::OnReplayState(const v1::ReplayState& replay, const StreamState& state) {
  status_->SetReplay(replay.paused(), replay.speed(), replay.frames(), replay.compare_run_id(),
                     replay.probe_set());
  if (!replay.error().empty()) spdlog::warn("replay of run {}: {}", state.run_id, replay.error());
}

void SubscriberLink::OnFrames(const v1::FrameBatch& batch, StreamState* state) {
  if (!state->showing) return;
  const bool ghosts = batch.ghost_frames_size() == batch.frames_size();
  int sent = 0;
  bool any_posed = false;
  const Clock::time_point begin = Clock::now();
  for (int i = 0; i < batch.frames_size() && !state->broken; ++i) {
    const v1::Frame& frame = batch.frames(i);
    const int tree_values = frame.q_size() > state->model_dofs && state->model_dofs > 0
                                ? state->model_dofs
                                : frame.q_size();
    state->q.assign(frame.q().begin(), frame.q().begin() + tree_values);
    bool posed = false;
    try {
      posed = slot_->WithScene([&](Scene& scene) {
        scene.SetJointValues(state->q);
        scene.ProbeReports(&state->probes);
        if (ghosts && scene.ghost()) {
          const v1::Frame& ghost = batch.ghost_frames(i);
          state->ghost_q.assign(ghost.q().begin(),
                                ghost.q().begin() + std::min(ghost.q_size(), tree_values));
          scene.ghost()->SetJointValues(state->ghost_q);
          status_->AddGhost(frame.t_s(), Distance(frame.tcp_m(), ghost.tcp_m()));
        }
        if (scene.contacts()) {
          ContactMarks(frame, &state->contacts);
          scene.contacts()->SetContacts(state->contacts);
          status_->AddContacts(static_cast<int>(state->contacts.size()));
        }
      });
    } catch (const std::exception& e) {  // InputError: the frame does not fit the scene
      spdlog::error("run {} frame {}: {}", state->run_id, frame.seq(), e.what());
      state->showing = false;
      break;
    }
    if (!posed) continue;
    any_posed = true;
    for (const ProbeReport& probe : state->probes) {
      v1::ProbeReport* report = state->reply.mutable_probe();
      report->set_run_id(state->run_id);
      report->set_seq(frame.seq());
      report->set_t_s(frame.t_s());
      report->set_probe(probe.name);
      report->mutable_position_m()->set_x(probe.position_m.x());
      report->mutable_position_m()->set_y(probe.position_m.y());
      report->mutable_position_m()->set_z(probe.position_m.z());
      report->set_frame(probe.frame);
      if (!Write(state->reply)) {  // the stream is gone: Finish says why
        state->broken = true;
        break;
      }
      ++sent;
    }
    if (sent > 0 && !state->probes_logged) {
      spdlog::info("run {}: answering with probe reports from frame {}", state->run_id,
                   frame.seq());
      state->probes_logged = true;
    }
  }
  const int64_t compute_ns =
      std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - begin).count();
  if (batch.frames_size() > 0) {
    status_->SetSeq(batch.frames(batch.frames_size() - 1).seq());
    status_->AddFrames(batch.frames(batch.frames_size() - 1).t_s(), batch.frames_size(),
                       batch.missed(), sent, compute_ns);
    if (posed_listener_ && any_posed) {
      slot_->WithScene([&](Scene& scene) { posed_listener_(scene, state->probes); });
    }
  } else if (batch.missed() > 0) {  // frames dropped just before the run's end
    status_->AddMissed(batch.missed());
  }
}

void SubscriberLink::OnRunEnded(const v1::RunInfo& ended, int* runs_ended, StreamState* state) {
  ++*runs_ended;
  status_->SetState("ended");
  spdlog::info("run {} ended: {} ({} frames)", ended.id(), v1::RunState_Name(ended.state()),
               ended.frames());
  if (!options_.follow ||
      (options_.exit_after_runs > 0 && *runs_ended >= options_.exit_after_runs)) {
    state->done = true;
  }
}

}  // namespace mbstream::viewer
