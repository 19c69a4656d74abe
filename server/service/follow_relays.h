// The runs of other replicas on a follow stream (docs/cluster.md, "Follow"): for each run the
// run manager announces (StreamEvent kRemoteRun), a relay opens Subscribe(run_id) on the
// replica integrating it, with the follower's token, and passes its events (run_started,
// frames, run_ended) on, unchanged, on the follow stream; the follower's probe reports of
// that run go back to that replica, which checks and stores them.
#pragma once

#include <grpcpp/server_context.h>

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/runs/run_manager.h"
#include "server/service/peer_channels.h"
#include "server/service/peer_proxy.h"

namespace mbstream {

class FollowRelays {
 public:
  // `write` sends an event on the follow stream (serialized with the stream's own events;
  // false when the stream is gone). None is owned; all outlive the relays. `contacts`: the
  // follower asked for the frames' contacts (SubscribeRequest.Start.contacts).
  FollowRelays(PeerChannels* peers, const RunManager* runs, const grpc::ServerContextBase* context,
               std::function<bool(const v1::SubscribeEvent&)> write, int max_batch, bool contacts);
  ~FollowRelays();  // Stop()

  // A run announced by the run manager: relayed from its replica if it integrates elsewhere
  // and no relay of it is open.
  void Open(const std::string& run_id);
  // A follower's message: true when it was a probe report of a relayed run (sent on to its
  // replica), false when it is for this replica.
  bool Divert(const v1::SubscribeRequest& request);
  // Cancels every relay and waits for their threads. Idempotent.
  void Stop();

 private:
  struct Relay {
    std::string run_id;
    std::unique_ptr<PeerSubscribe> upstream;  // set once connected (mutex_)
    std::thread thread;
    std::atomic<bool> done{false};
  };
  void Pass(Relay* relay, const v1::RunInfo& owner);

  PeerChannels* const peers_;
  const RunManager* const runs_;
  const grpc::ServerContextBase* const context_;
  const std::function<bool(const v1::SubscribeEvent&)> write_;
  const int max_batch_;
  const bool contacts_;
  std::mutex mutex_;
  bool stopped_ = false;
  std::vector<std::shared_ptr<Relay>> relays_;
};

}  // namespace mbstream
