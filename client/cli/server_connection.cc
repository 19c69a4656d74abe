#include "client/cli/server_connection.h"

#include <iostream>
#include <string>
#include <vector>

#include "shared/common/check.h"
#include "shared/common/did_you_mean.h"
#include "shared/net/tls_files.h"

namespace mbstream::cli {

void AddClientOptions(CLI::App& app, ClientOptions* options) {
  app.add_option("--server", options->server, "server address: host:port or unix:/path")
      ->envname("MBSTREAM_SERVER")
      ->capture_default_str();
  app.add_option("--ca", options->security.ca_file, "PEM CA of the server's certificate (TLS)")
      ->envname("MBSTREAM_CA")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-cert", options->security.cert_file, "client certificate (PEM)")
      ->check(CLI::ExistingFile);
  app.add_option("--tls-key", options->security.key_file, "client certificate's key (PEM)")
      ->check(CLI::ExistingFile);
  app.add_option("--token-file", options->security.token_file,
                 "file whose first word is the access token")
      ->envname("MBSTREAM_TOKEN_FILE")
      ->check(CLI::ExistingFile);
}

std::unique_ptr<v1::Simulation::Stub> ConnectSimulation(const ClientOptions& options) {
  try {
    return v1::Simulation::NewStub(net::MakeChannel(options.server, options.security));
  } catch (const net::SecurityConfigError& error) {
    throw InputError(error.what());
  }
}

namespace {

// The server's "no model 'NAME' on this server; known models: A (ID), B (ID) (...)": "; did you
// mean 'A'?" for the closest known name, or "".
std::string ModelDidYouMean(const std::string& message) {
  const std::string start = "no model '";
  const std::string list = "; known models: ";
  const size_t name_at = message.find(start);
  const size_t list_at = message.find(list);
  if (name_at == std::string::npos || list_at == std::string::npos) return "";
  const size_t name_end = message.find("' on this server", name_at);
  if (name_end == std::string::npos) return "";
  const std::string name =
      message.substr(name_at + start.size(), name_end - name_at - start.size());
  std::vector<std::string> known;
  size_t at = list_at + list.size();
  while (at < message.size()) {
    const size_t open = message.find(" (", at);
    if (open == std::string::npos) break;
    known.push_back(message.substr(at, open - at));
    const size_t next = message.find("), ", open);
    if (next == std::string::npos) break;
    at = next + 3;
  }
  return DidYouMean(name, known);
}

}  // namespace

int ReportRpcError(const std::string& command, const ClientOptions& options,
                   const grpc::Status& status) {
  std::cerr << "mbstream " << command << ": " << status.error_message();
  if (status.error_code() == grpc::StatusCode::NOT_FOUND) {
    std::cerr << ModelDidYouMean(status.error_message());
  }
  if (status.error_code() == grpc::StatusCode::UNAVAILABLE &&
      status.error_message().find("shutting down") == std::string::npos) {
    std::cerr << " (server " << options.server
              << "; is mbstream-server running there? set --server or MBSTREAM_SERVER)";
  }
  std::cerr << "\n";
  switch (status.error_code()) {
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::NOT_FOUND:
    case grpc::StatusCode::FAILED_PRECONDITION:
    case grpc::StatusCode::RESOURCE_EXHAUSTED:
    case grpc::StatusCode::UNAUTHENTICATED:
    case grpc::StatusCode::PERMISSION_DENIED:
      return 2;
    case grpc::StatusCode::UNAVAILABLE:
    case grpc::StatusCode::DEADLINE_EXCEEDED:
      return 3;
    default:
      return 1;
  }
}

}  // namespace mbstream::cli
