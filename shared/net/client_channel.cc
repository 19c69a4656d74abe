#include "shared/net/client_channel.h"

#include <grpcpp/create_channel.h>
#include <grpcpp/security/credentials.h>
#include <grpcpp/support/client_interceptor.h>

#include <vector>

#include "shared/net/tls_files.h"

namespace mbstream::net {

namespace {

// Adds `authorization: Bearer <token>` to every call's initial metadata. An interceptor,
// not call credentials, so that it also works on insecure local channels.
class BearerTokenInterceptor final : public grpc::experimental::Interceptor {
 public:
  explicit BearerTokenInterceptor(const std::string* header) : header_(header) {}
  void Intercept(grpc::experimental::InterceptorBatchMethods* methods) override {
    if (methods->QueryInterceptionHookPoint(
            grpc::experimental::InterceptionHookPoints::PRE_SEND_INITIAL_METADATA)) {
      methods->GetSendInitialMetadata()->insert({"authorization", *header_});
    }
    methods->Proceed();
  }

 private:
  const std::string* header_;
};

class BearerTokenFactory final : public grpc::experimental::ClientInterceptorFactoryInterface {
 public:
  explicit BearerTokenFactory(const std::string& token) : header_("Bearer " + token) {}
  grpc::experimental::Interceptor* CreateClientInterceptor(
      grpc::experimental::ClientRpcInfo*) override {
    return new BearerTokenInterceptor(&header_);
  }

 private:
  std::string header_;  // lives as long as the channel (the channel owns the factory)
};

std::string TokenOf(const ClientSecurity& security) {
  if (!security.token.empty()) return security.token;
  if (security.token_file.empty()) return "";
  std::string text = ReadSecurityFile(security.token_file, "--token-file");
  text = text.substr(0, text.find_first_of("\r\n"));
  const size_t space = text.find_first_of(" \t");  // a server token file line: token roles
  return text.substr(0, space);
}

}  // namespace

std::shared_ptr<grpc::Channel> MakeChannel(const std::string& address,
                                           const ClientSecurity& security, int max_message_bytes) {
  grpc::ChannelArguments arguments;
  arguments.SetMaxReceiveMessageSize(max_message_bytes);
  arguments.SetMaxSendMessageSize(max_message_bytes);
  const std::string token = TokenOf(security);
  std::shared_ptr<grpc::ChannelCredentials> credentials;
  if (security.ca_file.empty()) {
    if (!token.empty() && !IsLocalAddress(address)) {
      throw SecurityConfigError("refusing to send a token in the clear to " + address +
                                "; give the server's CA with --ca (TLS)");
    }
    credentials = grpc::InsecureChannelCredentials();
  } else {
    grpc::SslCredentialsOptions options;
    options.pem_root_certs = ReadSecurityFile(security.ca_file, "--ca");
    if (!security.cert_file.empty()) {
      options.pem_cert_chain = ReadSecurityFile(security.cert_file, "--tls-cert");
      options.pem_private_key = ReadSecurityFile(security.key_file, "--tls-key");
    }
    credentials = grpc::SslCredentials(options);
  }
  if (!token.empty()) {
    std::vector<std::unique_ptr<grpc::experimental::ClientInterceptorFactoryInterface>> factories;
    factories.push_back(std::make_unique<BearerTokenFactory>(token));
    return grpc::experimental::CreateCustomChannelWithInterceptors(address, credentials, arguments,
                                                                   std::move(factories));
  }
  return grpc::CreateCustomChannel(address, credentials, arguments);
}

}  // namespace mbstream::net
