#include "server/service/peer_proxy.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <thread>

#include "server/runs/request_error.h"

namespace mbstream {

namespace {

constexpr auto kQueuedPoll = std::chrono::milliseconds(50);  // a queued run's claim, looked for
constexpr auto kCancelTimeout = std::chrono::seconds(10);

}  // namespace

std::optional<v1::RunInfo> RemoteOwner(PeerChannels* peers, const RunManager& runs,
                                       const std::string& run_id,
                                       const grpc::ServerContextBase& context,
                                       const std::atomic<bool>& stopping, bool wait_queued) {
  if (peers == nullptr || !runs.replica().shared_store() || PeerChannels::IsProxied(context)) {
    return std::nullopt;
  }
  for (;;) {
    ReplicaControl::RunPlace place = runs.replica().Locate(run_id);
    using Where = ReplicaControl::RunPlace::Where;
    if (place.where == Where::kElsewhere) return std::move(place.info);
    if (place.where != Where::kQueued || !wait_queued) return std::nullopt;
    if (context.IsCancelled() || stopping) return std::nullopt;
    std::this_thread::sleep_for(kQueuedPoll);
  }
}

grpc::Status OwnerStatus(const grpc::Status& status, const v1::RunInfo& owner) {
  switch (status.error_code()) {
    case grpc::StatusCode::UNAVAILABLE:
      return grpc::Status(grpc::StatusCode::UNAVAILABLE,
                          PeerChannels::Where(owner) + ", which went away or cannot be reached (" +
                              status.error_message() +
                              "); its run is marked when its lease expires; retry then");
    case grpc::StatusCode::DEADLINE_EXCEEDED:
      return grpc::Status(
          grpc::StatusCode::DEADLINE_EXCEEDED,
          PeerChannels::Where(owner) + ", which did not answer in time: " + status.error_message());
    default:
      return status;
  }
}

PeerSubscribe::PeerSubscribe(PeerChannels& peers, const grpc::ServerContextBase& caller,
                             const v1::RunInfo& owner, const v1::SubscribeRequest& start)
    : owner_(owner) {
  std::shared_ptr<grpc::Channel> channel = peers.Connect(owner_);
  context_ = peers.ContextFor(caller);
  stub_ = v1::Simulation::NewStub(channel);
  stream_ = stub_->Subscribe(context_.get());
  (void)stream_->Write(start);  // a failure shows as the end of Read, then in Finish
}

PeerSubscribe::~PeerSubscribe() {
  if (!finished_) {
    context_->TryCancel();
    (void)Finish();
  }
}

bool PeerSubscribe::Write(const v1::SubscribeRequest& request) {
  std::lock_guard<std::mutex> lock(write_mutex_);
  return !writes_done_ && stream_->Write(request);
}

void PeerSubscribe::WritesDone() {
  std::lock_guard<std::mutex> lock(write_mutex_);
  if (writes_done_) return;
  writes_done_ = true;
  (void)stream_->WritesDone();
}

grpc::Status PeerSubscribe::Finish() {
  std::lock_guard<std::mutex> lock(write_mutex_);
  writes_done_ = true;  // no Write once the call ends
  finished_ = true;
  return OwnerStatus(stream_->Finish(), owner_);
}

grpc::Status ProxyWatchRun(PeerChannels& peers, const grpc::ServerContextBase& context,
                           const v1::WatchRunRequest& request,
                           const std::function<bool(const v1::WatchEvent&)>& write,
                           const v1::RunInfo& owner) {
  std::shared_ptr<grpc::Channel> channel = peers.Connect(owner);
  std::unique_ptr<grpc::ClientContext> upstream = peers.ContextFor(context);
  std::unique_ptr<v1::Simulation::Stub> stub = v1::Simulation::NewStub(channel);
  std::unique_ptr<grpc::ClientReader<v1::WatchEvent>> reader =
      stub->WatchRun(upstream.get(), request);
  v1::WatchEvent event;
  while (reader->Read(&event)) {
    if (!write(event)) {
      upstream->TryCancel();
      (void)reader->Finish();
      return grpc::Status(grpc::StatusCode::CANCELLED, "client gone");
    }
  }
  return OwnerStatus(reader->Finish(), owner);
}

grpc::Status ProxyCancelRun(PeerChannels& peers, const grpc::ServerContextBase& context,
                            const v1::CancelRunRequest& request, const v1::RunInfo& owner,
                            v1::RunInfo* response) {
  grpc::Status status;
  try {
    std::shared_ptr<grpc::Channel> channel = peers.Connect(owner);
    std::unique_ptr<grpc::ClientContext> upstream = peers.ContextFor(context);
    const auto deadline = std::chrono::system_clock::now() + kCancelTimeout;
    if (upstream->deadline() > deadline) upstream->set_deadline(deadline);
    status = v1::Simulation::NewStub(channel)->CancelRun(upstream.get(), request, response);
  } catch (const RequestError& error) {  // cannot connect: the message names the owner
    return grpc::Status(
        grpc::StatusCode::FAILED_PRECONDITION,
        std::string(error.what()) + "; the run is marked INTERRUPTED when its lease expires");
  }
  if (status.error_code() == grpc::StatusCode::UNAVAILABLE ||
      status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED) {
    return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION,
                        PeerChannels::Where(owner) +
                            ", which could not cancel it: " + status.error_message() +
                            "; the run is marked INTERRUPTED when its lease expires");
  }
  if (status.ok())
    spdlog::info("run {} cancelled through its replica {}", owner.id(), owner.replica());
  return status;
}

}  // namespace mbstream
