#include "client/cli/server_connection.h"

#include <iostream>

namespace mbstream::cli {

std::unique_ptr<v1::Simulation::Stub> ConnectSimulation(const ClientOptions& options) {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(256 << 20);
  arguments.SetMaxSendMessageSize(256 << 20);
  return v1::Simulation::NewStub(
      grpc::CreateCustomChannel(options.server, grpc::InsecureChannelCredentials(), arguments));
}

int ReportRpcError(const std::string& command, const ClientOptions& options,
                   const grpc::Status& status) {
  std::cerr << "mbstream " << command << ": " << status.error_message();
  if (status.error_code() == grpc::StatusCode::UNAVAILABLE) {
    std::cerr << " (server " << options.server
              << "; is mbstream-server running there? set --server or MBSTREAM_SERVER)";
  }
  std::cerr << "\n";
  switch (status.error_code()) {
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::NOT_FOUND:
    case grpc::StatusCode::FAILED_PRECONDITION:
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
      return 2;
    case grpc::StatusCode::UNAVAILABLE:
    case grpc::StatusCode::DEADLINE_EXCEEDED:
      return 3;
    default:
      return 1;
  }
}

}  // namespace mbstream::cli
