// Channels from this replica to the other replicas of a cluster (docs/cluster.md, "Calls
// for runs on other replicas"): a gRPC client inside the server, used to proxy WatchRun,
// Subscribe and CancelRun of a run integrating elsewhere to the replica that runs it.
//
// Security between replicas: TLS when this server has TLS (--tls-cert), trusting --peer-ca
// (default: --tls-client-ca when given, else the system's CAs), presenting this server's
// certificate when peers require client certificates (--tls-client-ca); insecure when this
// server has no TLS. Every proxied call carries the caller's `authorization` metadata, so the
// owner applies its own role check, and `mbstream-proxied-by` (this replica's id), so a
// proxied call is never proxied again.
#pragma once

#include <grpcpp/channel.h>
#include <grpcpp/client_context.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/server_context.h>

#include <chrono>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "mbstream/v1/run.pb.h"

namespace mbstream {

struct PeerSecurity {
  bool tls = false;       // TLS to peers (this server has TLS)
  std::string ca_file;    // PEM CA trusted for peers' certificates; empty: the system's CAs
  std::string cert_file;  // presented to peers that require client certificates; may be empty
  std::string key_file;
  std::string tls_name;  // checked in peers' certificates; empty: their advertised host
};

class PeerChannels {
 public:
  // How long a proxy waits for a peer's connection before answering UNAVAILABLE.
  static constexpr std::chrono::seconds kConnectTimeout{3};
  // Metadata key marking a call proxied by another replica (its value: that replica's id).
  static constexpr const char* kProxiedBy = "mbstream-proxied-by";

  // Reads the security files at once; throws net::SecurityConfigError naming the flag.
  PeerChannels(const PeerSecurity& security, std::string replica_id);

  // A connected channel to `address` (cached per address), or throws RequestError
  // (kUnavailable) naming run `owner`'s replica and address when it cannot connect within
  // kConnectTimeout (failing as soon as the connection fails).
  std::shared_ptr<grpc::Channel> Connect(const v1::RunInfo& owner);
  // A client context for a call made on behalf of `caller`: cancelled with it (and its
  // deadline), with its authorization metadata and kProxiedBy.
  std::unique_ptr<grpc::ClientContext> ContextFor(const grpc::ServerContextBase& caller) const;

  // Whether `context`'s call was proxied here by another replica.
  static bool IsProxied(const grpc::ServerContextBase& context);
  // "run R integrates on replica X (host:port)", for messages.
  static std::string Where(const v1::RunInfo& owner);

 private:
  std::shared_ptr<grpc::ChannelCredentials> credentials_;
  std::string tls_name_;
  const std::string replica_id_;
  std::mutex mutex_;
  std::map<std::string, std::shared_ptr<grpc::Channel>> channels_;
};

}  // namespace mbstream
