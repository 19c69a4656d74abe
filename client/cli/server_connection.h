// How the CLI reaches a server: the global --server option and the channel.
#pragma once

#include <grpcpp/grpcpp.h>
#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "mbstream/v1/simulation_service.grpc.pb.h"
#include "shared/net/client_channel.h"

namespace mbstream::cli {

struct ClientOptions {
  std::string server = "127.0.0.1:50051";  // --server or $MBSTREAM_SERVER
  net::ClientSecurity security;            // --ca, --tls-cert, --tls-key, --token-file
};

// Declares --server, --ca, --tls-cert, --tls-key and --token-file on `app`.
void AddClientOptions(CLI::App& app, ClientOptions* options);

// A stub on a channel to options.server: TLS when a CA is given, else insecure (loopback
// and unix sockets); the token, if any, on every call; large message limits for results.
// Throws InputError for unusable security settings.
std::unique_ptr<v1::Simulation::Stub> ConnectSimulation(const ClientOptions& options);

// Prints "mbstream <command>: <server's message>" (with a hint when the server cannot be
// reached) and returns the exit code: 2 for a bad request (INVALID_ARGUMENT, NOT_FOUND,
// FAILED_PRECONDITION, RESOURCE_EXHAUSTED), 3 when the server is unreachable, 1 otherwise.
int ReportRpcError(const std::string& command, const ClientOptions& options,
                   const grpc::Status& status);

}  // namespace mbstream::cli
