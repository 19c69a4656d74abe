// Server-side credentials: TLS from certificate files, or insecure.
#pragma once

#include <grpcpp/security/server_credentials.h>

#include <memory>
#include <string>

namespace mbstream::net {

struct ServerTls {
  std::string cert_file;       // PEM certificate chain; empty = no TLS
  std::string key_file;        // PEM private key
  std::string client_ca_file;  // PEM CA: when set, clients must present a certificate it signed
  bool enabled() const { return !cert_file.empty(); }
};

// TLS credentials from `tls` (both cert and key needed), or insecure ones when it is empty.
// Throws SecurityConfigError naming the flag and file.
std::shared_ptr<grpc::ServerCredentials> MakeServerCredentials(const ServerTls& tls);

}  // namespace mbstream::net
