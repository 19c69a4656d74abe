#include "viewer/web/page_access.h"

#include <grpcpp/client_context.h>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "shared/net/tls_files.h"

namespace mbstream::viewer {

namespace {
constexpr auto kAdmittedFor = std::chrono::seconds(60);
constexpr auto kCheckDeadline = std::chrono::seconds(10);

template <class Request, class Response>
struct Call {
  grpc::ClientContext context;
  Request request;
  Response response;
  explicit Call(const std::string& token) {
    context.set_deadline(std::chrono::system_clock::now() + kCheckDeadline);
    if (!token.empty()) context.AddMetadata("authorization", "Bearer " + token);
  }
};
}  // namespace

struct PageAccess::State {
  struct Admitted {
    std::chrono::steady_clock::time_point until;
    WebOptions::Access access;
  };
  std::string address;
  bool clear_text = false;  // tokens would cross the network unencrypted
  bool replay_controls = false;
  std::unique_ptr<v1::Simulation::Stub> stub;
  std::mutex mutex;                          // guards `admitted`
  std::map<std::string, Admitted> admitted;  // token -> verdict

  void Remember(const std::string& token, const WebOptions::Access& access) {
    std::lock_guard<std::mutex> lock(mutex);
    if (admitted.size() > 1000) admitted.clear();
    admitted[token] = {std::chrono::steady_clock::now() + kAdmittedFor, access};
  }
};

namespace {

// Whether an admitted token may steer the replay: ReplayRun's role (run) asked with a request
// that the server refuses after its role gate and before it does anything (speed -1 is out of
// range, and run "" does not exist): INVALID_ARGUMENT (or NOT_FOUND) says the gate let it
// through, PERMISSION_DENIED that the token lacks the role.
void CheckControls(std::shared_ptr<PageAccess::State> state, const std::string& token,
                   std::function<void(WebOptions::Access)> done) {
  auto call = std::make_shared<Call<v1::ReplayRunRequest, v1::RunInfo>>(token);
  call->request.set_speed(-1.0);
  state->stub->async()->ReplayRun(
      &call->context, &call->request, &call->response,
      [state, call, token, done = std::move(done)](grpc::Status status) {
        WebOptions::Access access;
        switch (status.error_code()) {
          case grpc::StatusCode::INVALID_ARGUMENT:
          case grpc::StatusCode::NOT_FOUND:
          case grpc::StatusCode::FAILED_PRECONDITION:
            break;
          case grpc::StatusCode::PERMISSION_DENIED:
            access.controls = false;
            access.message =
                "this token may watch but not steer the replay: its controls act for every page "
                "and the viewer's window, which needs the run role";
            break;
          default:  // not remembered: asked again by the next page
            access.controls = false;
            access.message = "could not check whether this token may steer the replay: " +
                             status.error_message();
            return done(access);
        }
        state->Remember(token, access);
        done(access);
      });
}

}  // namespace

PageAccess::PageAccess(const std::string& server_address, net::ClientSecurity security,
                       bool replay_controls)
    : state_(std::make_shared<State>()) {
  security.token.clear();
  security.token_file.clear();
  state_->address = server_address;
  state_->clear_text = security.ca_file.empty() && !net::IsLocalAddress(server_address);
  state_->replay_controls = replay_controls;
  state_->stub = v1::Simulation::NewStub(net::MakeChannel(server_address, security));
}

void PageAccess::Check(const std::string& token, std::function<void(WebOptions::Access)> done) {
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    const auto found = state_->admitted.find(token);
    if (found != state_->admitted.end() && found->second.until > std::chrono::steady_clock::now()) {
      return done(found->second.access);
    }
  }
  if (!token.empty() && state_->clear_text) {
    return done({403, "the viewer does not send tokens in the clear to " + state_->address +
                          " (give mbstream-viewer --ca for TLS)"});
  }
  auto call = std::make_shared<Call<v1::ListRunsRequest, v1::ListRunsResponse>>(token);
  call->request.set_limit(1);
  call->request.set_page_size(1);
  state_->stub->async()->ListRuns(
      &call->context, &call->request, &call->response,
      [state = state_, call, token, done = std::move(done)](grpc::Status status) {
        switch (status.error_code()) {
          case grpc::StatusCode::OK: {
            if (state->replay_controls) return CheckControls(state, token, done);
            const WebOptions::Access access{0, "the viewer shows live runs: nothing to steer",
                                            false};
            state->Remember(token, access);
            return done(access);
          }
          case grpc::StatusCode::UNAUTHENTICATED:
            return done({401, token.empty() ? "the simulation server requires a token"
                                            : "the simulation server does not know this token"});
          case grpc::StatusCode::PERMISSION_DENIED:
            return done({403, "this token may not watch runs (it needs the view role)"});
          default:
            return done({503, "could not check the token with the simulation server " +
                                  state->address + ": " + status.error_message()});
        }
      });
}

}  // namespace mbstream::viewer
