// The viewer's network side: subscribes to the simulation server, shows each run's scene,
// poses it for every frame and answers every frame with its probes (on this thread, so
// probes never wait for a render). Reconnects with back-off when the server goes away.
#pragma once

#include <atomic>
#include <string>

#include "net/client_channel.h"
#include "viewer/link/link_status.h"
#include "viewer/link/run_scene.h"
#include "viewer/link/scene_slot.h"

namespace mbstream::viewer {

struct LinkOptions {
  std::string server;            // host:port or unix:/path
  net::ClientSecurity security;  // --ca, --tls-cert/--tls-key, --token-file
  std::string run_id;            // one run; empty with follow
  bool follow = false;           // every new run
  int exit_after_runs = 0;       // follow: stop after this many runs ended; 0 = never
  int max_batch = 64;            // frames per message asked of the server
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

 private:
  enum class StreamEnd { kDone, kRetry, kFatal };
  StreamEnd Stream(int* runs_ended);

  LinkOptions options_;
  RunSceneSource scenes_;
  SceneSlot* slot_;
  LinkStatus* status_;
  std::atomic<bool> stop_{false};
  std::atomic<void*> context_{nullptr};  // grpc::ClientContext of the open stream
};

}  // namespace mbstream::viewer
