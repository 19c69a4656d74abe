// Proxies of calls about a run integrating on another replica (docs/cluster.md, "Calls for
// runs on other replicas"): WatchRun and Subscribe relayed message by message (bit for bit)
// from the owner, Subscribe both ways (a viewer's probe reports reach the owner, which checks
// and stores them), CancelRun forwarded. The owner applies its own role check to the caller's
// forwarded token. The owner unreachable or gone: UNAVAILABLE naming it (FAILED_PRECONDITION
// for CancelRun); the caller gone: the call to the owner is cancelled with it.
#pragma once

#include <grpcpp/server_context.h>

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "server/runs/run_manager.h"
#include "server/service/peer_channels.h"

namespace mbstream {

// The run's info when its frames must come from another replica (it integrates there), else
// nullopt (here, or ended: served from this replica and the store). With `wait_queued`, a run
// queued in a shared store is waited for until a replica claims it (the caller gone or
// `stopping` end the wait: nullopt). Never for a call proxied here already, nor without peers.
std::optional<v1::RunInfo> RemoteOwner(PeerChannels* peers, const RunManager& runs,
                                       const std::string& run_id,
                                       const grpc::ServerContextBase& context,
                                       const std::atomic<bool>& stopping, bool wait_queued);

// One Subscribe call to the owner of a run, on behalf of a stream of this replica. Write and
// WritesDone may be called from another thread than Read.
class PeerSubscribe {
 public:
  // Connects (PeerChannels::Connect: throws RequestError(kUnavailable) naming the owner) and
  // sends `start`.
  PeerSubscribe(PeerChannels& peers, const grpc::ServerContextBase& caller,
                const v1::RunInfo& owner, const v1::SubscribeRequest& start);
  ~PeerSubscribe();  // cancels the call if it has not finished

  bool Read(v1::SubscribeEvent* event) { return stream_->Read(event); }
  bool Write(const v1::SubscribeRequest& request);
  void WritesDone();  // once; later Writes fail
  void Cancel() { context_->TryCancel(); }
  // After Read returned false: the owner's status; a lost connection becomes UNAVAILABLE
  // naming the owner.
  grpc::Status Finish();
  const v1::RunInfo& owner() const { return owner_; }

 private:
  const v1::RunInfo owner_;
  std::unique_ptr<grpc::ClientContext> context_;
  std::unique_ptr<v1::Simulation::Stub> stub_;
  std::unique_ptr<grpc::ClientReaderWriter<v1::SubscribeRequest, v1::SubscribeEvent>> stream_;
  std::mutex write_mutex_;
  bool writes_done_ = false;
  bool finished_ = false;
};

// The owner's status of a proxied call, with UNAVAILABLE (connection lost or refused) and
// DEADLINE_EXCEEDED messages naming the owner.
grpc::Status OwnerStatus(const grpc::Status& status, const v1::RunInfo& owner);

// WatchRun relayed from the owner, event by event, each passed to `write` (false: the
// watcher is gone, the call to the owner is cancelled).
grpc::Status ProxyWatchRun(PeerChannels& peers, const grpc::ServerContextBase& context,
                           const v1::WatchRunRequest& request,
                           const std::function<bool(const v1::WatchEvent&)>& write,
                           const v1::RunInfo& owner);

// CancelRun forwarded to the owner (at most kCancelTimeout); FAILED_PRECONDITION naming the
// owner when it cannot be reached.
grpc::Status ProxyCancelRun(PeerChannels& peers, const grpc::ServerContextBase& context,
                            const v1::CancelRunRequest& request, const v1::RunInfo& owner,
                            v1::RunInfo* response);

}  // namespace mbstream
