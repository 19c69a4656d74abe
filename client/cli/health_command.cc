// `mbstream health [--service NAME]`: asks the server's gRPC health service (grpc.health.v1)
// whether it is serving; prints SERVING, NOT_SERVING or UNKNOWN and exits 0 only for
// SERVING. Kubernetes' readiness probe runs it (deploy/k8s/), as its own gRPC probe cannot
// speak TLS.
#include <chrono>
#include <cstdio>

#include "client/cli/server_commands.h"
#include "grpc/health/v1/health.grpc.pb.h"

namespace mbstream::cli {

namespace {

constexpr int kNotServing = 4;  // exit code: reachable but not serving

int CheckHealth(const ClientOptions& client, const std::string& service) {
  auto stub = grpc::health::v1::Health::NewStub(net::MakeChannel(client.server, client.security));
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(5));
  grpc::health::v1::HealthCheckRequest request;
  request.set_service(service);
  grpc::health::v1::HealthCheckResponse response;
  const grpc::Status status = stub->Check(&context, request, &response);
  if (!status.ok()) return ReportRpcError("health", client, status);
  std::printf("%s\n",
              grpc::health::v1::HealthCheckResponse::ServingStatus_Name(response.status()).c_str());
  return response.status() == grpc::health::v1::HealthCheckResponse::SERVING ? 0 : kNotServing;
}

}  // namespace

void AddHealthCommand(CLI::App& app, std::shared_ptr<const ClientOptions> client, int* exit_code) {
  auto service = std::make_shared<std::string>();
  CLI::App* health = app.add_subcommand(
      "health", "ask the server's gRPC health service; exit 0 only when SERVING (4 when not)");
  health->add_option("--service", *service,
                     "a service name (default: the whole server; mbstream.new_runs: whether it "
                     "accepts new runs, NOT_SERVING while its disk is below --min-free-mb)");
  health->callback([client, service, exit_code] { *exit_code = CheckHealth(*client, *service); });
}

}  // namespace mbstream::cli
