#include "shared/net/server_credentials.h"

#include <grpcpp/security/server_credentials.h>

#include "shared/net/tls_files.h"

namespace mbstream::net {

std::shared_ptr<grpc::ServerCredentials> MakeServerCredentials(const ServerTls& tls) {
  if (!tls.enabled() && tls.key_file.empty()) return grpc::InsecureServerCredentials();
  if (tls.cert_file.empty() || tls.key_file.empty()) {
    throw SecurityConfigError("TLS needs both --tls-cert and --tls-key");
  }
  grpc::SslServerCredentialsOptions options(
      tls.client_ca_file.empty() ? GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE
                                 : GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
  options.pem_key_cert_pairs.push_back(
      {ReadSecurityFile(tls.key_file, "--tls-key"), ReadSecurityFile(tls.cert_file, "--tls-cert")});
  if (!tls.client_ca_file.empty()) {
    options.pem_root_certs = ReadSecurityFile(tls.client_ca_file, "--tls-client-ca");
  }
  return grpc::SslServerCredentials(options);
}

}  // namespace mbstream::net
