// The viewer's network side: subscribes to the simulation server, shows each run's scene,
// poses it for every frame and answers every frame with its probes (on this thread, so
// probes never wait for a render). Reconnects with back-off when the server goes away.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <mutex>
#include <span>
#include <string>

#include "mbstream/v1/simulation_service.pb.h"

#include "shared/net/client_channel.h"
#include "viewer/link/link_status.h"
#include "viewer/link/run_scene.h"
#include "viewer/link/scene_slot.h"

namespace mbstream::viewer {

// --run of an ended run: how to replay it (replay.proto). A run still running is shown live.
struct ReplayOptions {
  double speed = 1.0;  // simulated s per wall s; 0 = as fast as the viewer takes frames
  bool loop = false;
  int64_t from_seq = 0;
  bool paused = false;
  std::string compare_run_id;  // --compare: this run as a translucent ghost
  std::string scene_tag;       // the probe set's scene tag (the --scene file, or the model's)
};

struct LinkOptions {
  std::string server;            // host:port or unix:/path
  net::ClientSecurity security;  // --ca, --tls-cert/--tls-key, --token-file
  std::string run_id;            // one run; empty with follow
  bool follow = false;           // every new run
  int exit_after_runs = 0;       // follow: stop after this many runs ended; 0 = never
  int max_batch = 64;            // frames per message asked of the server
  ReplayOptions replay;          // with run_id
  bool contacts = false;         // --contacts: ask for the frames' contacts and draw them
  double contact_scale = 0.0;    // --contact-scale: m per N of the force arrows; 0 = automatic
};

class SubscriberLink {
 public:
  SubscriberLink(LinkOptions options, RunSceneSource scenes, SceneSlot* slot, LinkStatus* status);

  // Runs until the run ended (--run), `exit_after_runs` runs ended, Stop(), or a fatal error
  // (unknown run, bad credentials, a scene that does not fit the run's model in --run mode).
  // Returns the exit code: 0, or 1 after logging what is wrong.
  int Run();
  // From another thread (a signal): ends Run() soon.
  void Stop();
  // From another thread (the window's keys): sends a replay's time control on the open
  // stream; false when no stream is open.
  bool SendControl(const v1::ReplayControl& control);
  // Before Run(): called on the link's thread after each batch of frames posed the scene
  // (the status already updated), under the slot's lock, with the newest frame's probes.
  using PosedListener = std::function<void(Scene&, std::span<const ProbeReport>)>;
  void SetPosedListener(PosedListener listener) { posed_listener_ = std::move(listener); }

 private:
  enum class StreamEnd { kDone, kRetry, kFatal };
  // The current run of one open stream and its reusable buffers (subscriber_link.cc).
  struct StreamState;

  // One connection: subscribes, handles events until the end, returns how it ended.
  StreamEnd Stream(int* runs_ended);
  // The stream's first message: follow, or one run (and its replay settings).
  v1::SubscribeRequest StartRequest() const;
  // Hands one event to its handler; false when the server said it is closing the stream.
  bool Dispatch(const v1::SubscribeEvent& event, int* runs_ended, StreamState* state);
  // One handler per event kind; each updates `state` (the run shown, whether to stop).
  void OnRunStarted(const v1::SubscribeEvent::RunStarted& started, StreamState* state);
  void OnReplayState(const v1::ReplayState& replay, const StreamState& state);
  void OnFrames(const v1::FrameBatch& batch, StreamState* state);
  void OnRunEnded(const v1::RunInfo& ended, int* runs_ended, StreamState* state);
  // Shows the run's scene; returns what is wrong (empty when the scene is shown).
  std::string ShowRun(const v1::SubscribeEvent::RunStarted& started);
  // Writes one message on the open stream; false when the stream is broken.
  bool Write(const v1::SubscribeRequest& request);

  LinkOptions options_;
  PosedListener posed_listener_;
  RunSceneSource scenes_;
  SceneSlot* slot_;
  LinkStatus* status_;
  std::atomic<bool> stop_{false};
  // grpc::ClientContext of the open stream, null when none. Guarded by context_mutex_, so that
  // Stop() never cancels a context being destroyed (it did, and gRPC aborted).
  std::mutex context_mutex_;
  void* context_ = nullptr;
  std::mutex write_mutex_;  // one writer at a time on the open stream
  // grpc::ClientReaderWriter of the open stream, guarded by write_mutex_; null when none.
  void* writer_ = nullptr;
};

}  // namespace mbstream::viewer
