#include "server/service/peer_channels.h"

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/support/channel_arguments.h>

#include "server/runs/request_error.h"
#include "shared/net/tls_files.h"

namespace mbstream {

PeerChannels::PeerChannels(const PeerSecurity& security, std::string replica_id)
    : replica_id_(std::move(replica_id)) {
  if (!security.tls) {
    credentials_ = grpc::InsecureChannelCredentials();
    return;
  }
  grpc::SslCredentialsOptions options;
  if (!security.ca_file.empty()) {
    options.pem_root_certs = net::ReadSecurityFile(security.ca_file, "--peer-ca");
  }
  if (!security.cert_file.empty()) {
    options.pem_cert_chain = net::ReadSecurityFile(security.cert_file, "--tls-cert");
    options.pem_private_key = net::ReadSecurityFile(security.key_file, "--tls-key");
  }
  credentials_ = grpc::SslCredentials(options);
  tls_name_ = security.tls_name;
}

std::shared_ptr<grpc::Channel> PeerChannels::Connect(const v1::RunInfo& owner) {
  const std::string& address = owner.replica_address();
  if (address.empty()) {
    throw RequestError(RequestErrorKind::kUnavailable,
                       Where(owner) + ", which advertises no address; ask that replica");
  }
  std::shared_ptr<grpc::Channel> channel;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::shared_ptr<grpc::Channel>& cached = channels_[address];
    if (!cached) {
      grpc::ChannelArguments args;
      // A peer that vanishes without closing its connections (a host or network gone) is
      // noticed by keepalive pings within 30 s; one killed closes them at once.
      args.SetInt(GRPC_ARG_KEEPALIVE_TIME_MS, 20000);
      args.SetInt(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, 10000);
      args.SetInt(GRPC_ARG_MAX_RECEIVE_MESSAGE_LENGTH, -1);
      args.SetInt(GRPC_ARG_MAX_SEND_MESSAGE_LENGTH, -1);
      if (!tls_name_.empty()) args.SetSslTargetNameOverride(tls_name_);
      cached = grpc::CreateCustomChannel(address, credentials_, args);
    }
    channel = cached;
  }
  const auto deadline = std::chrono::system_clock::now() + kConnectTimeout;
  for (;;) {
    const grpc_connectivity_state state = channel->GetState(true);
    if (state == GRPC_CHANNEL_READY) return channel;
    if (state == GRPC_CHANNEL_TRANSIENT_FAILURE || state == GRPC_CHANNEL_SHUTDOWN ||
        !channel->WaitForStateChange(state, deadline)) {
      throw RequestError(
          RequestErrorKind::kUnavailable,
          Where(owner) + ", which cannot be reached (" +
              (state == GRPC_CHANNEL_TRANSIENT_FAILURE
                   ? "connection failed"
                   : "no connection within " + std::to_string(kConnectTimeout.count()) + " s") +
              "); retry when its runs are reaped");
    }
  }
}

std::unique_ptr<grpc::ClientContext> PeerChannels::ContextFor(
    const grpc::ServerContextBase& caller) const {
  std::unique_ptr<grpc::ClientContext> context = grpc::ClientContext::FromServerContext(caller);
  for (const auto& [key, value] : caller.client_metadata()) {
    if (key == "authorization") {
      context->AddMetadata("authorization", std::string(value.data(), value.size()));
    }
  }
  context->AddMetadata(kProxiedBy, replica_id_);
  return context;
}

bool PeerChannels::IsProxied(const grpc::ServerContextBase& context) {
  return context.client_metadata().count(kProxiedBy) > 0;
}

std::string PeerChannels::Where(const v1::RunInfo& owner) {
  return "run " + owner.id() + " integrates on replica " + owner.replica() + " (" +
         owner.replica_address() + ")";
}

}  // namespace mbstream
