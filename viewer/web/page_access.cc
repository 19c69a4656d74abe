#include "viewer/web/page_access.h"

#include <grpcpp/client_context.h>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "net/tls_files.h"

namespace mbstream::viewer {

namespace {
constexpr auto kAdmittedFor = std::chrono::seconds(60);
}  // namespace

struct PageAccess::State {
  std::string address;
  bool clear_text = false;  // tokens would cross the network unencrypted
  std::unique_ptr<v1::Simulation::Stub> stub;
  std::mutex mutex;                                                       // guards `admitted`
  std::map<std::string, std::chrono::steady_clock::time_point> admitted;  // token -> until
};

PageAccess::PageAccess(const std::string& server_address, net::ClientSecurity security)
    : state_(std::make_shared<State>()) {
  security.token.clear();
  security.token_file.clear();
  state_->address = server_address;
  state_->clear_text = security.ca_file.empty() && !net::IsLocalAddress(server_address);
  state_->stub = v1::Simulation::NewStub(net::MakeChannel(server_address, security));
}

void PageAccess::Check(const std::string& token, std::function<void(WebOptions::Access)> done) {
  {
    std::lock_guard<std::mutex> lock(state_->mutex);
    const auto found = state_->admitted.find(token);
    if (found != state_->admitted.end() && found->second > std::chrono::steady_clock::now()) {
      return done({});
    }
  }
  if (!token.empty() && state_->clear_text) {
    return done({403, "the viewer does not send tokens in the clear to " + state_->address +
                          " (give mbstream-viewer --ca for TLS)"});
  }
  struct Call {
    grpc::ClientContext context;
    v1::ListRunsRequest request;
    v1::ListRunsResponse response;
  };
  auto call = std::make_shared<Call>();
  call->request.set_limit(1);
  call->request.set_page_size(1);
  call->context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
  if (!token.empty()) call->context.AddMetadata("authorization", "Bearer " + token);
  state_->stub->async()->ListRuns(
      &call->context, &call->request, &call->response,
      [state = state_, call, token, done = std::move(done)](grpc::Status status) {
        switch (status.error_code()) {
          case grpc::StatusCode::OK: {
            std::lock_guard<std::mutex> lock(state->mutex);
            if (state->admitted.size() > 1000) state->admitted.clear();
            state->admitted[token] = std::chrono::steady_clock::now() + kAdmittedFor;
            return done({});
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
