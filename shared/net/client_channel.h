// Client-side channels: insecure for local addresses, TLS with a CA file, optional client
// certificate, and a bearer token attached to every call.
#pragma once

#include <grpcpp/channel.h>

#include <memory>
#include <string>

namespace mbstream::net {

struct ClientSecurity {
  std::string ca_file;     // PEM CA that signed the server's certificate; empty = insecure
  std::string cert_file;   // client certificate (servers that require one)
  std::string key_file;    // its private key
  std::string token;       // sent as `authorization: Bearer <token>`; empty = none
  std::string token_file;  // or read from this file (first line)
};

// A channel to `address` (host:port or unix:/path). Without a CA file the channel is
// insecure, which is refused for non-local addresses when a token would be sent in the
// clear. Throws SecurityConfigError with what to do.
std::shared_ptr<grpc::Channel> MakeChannel(const std::string& address,
                                           const ClientSecurity& security,
                                           int max_message_bytes = 256 << 20);

}  // namespace mbstream::net
