// Token authentication and roles: who may call what.
//
// Token file (mbstream-server --token-file): one token per line followed by its roles,
//   <token> <role>[,<role>...]     roles: submit, run, view, admin (admin = all)
// blank lines and lines starting with '#' are ignored. Clients send
// `authorization: Bearer <token>`. Tokens never appear in logs or error messages.
#pragma once

#include <grpcpp/server_context.h>
#include <grpcpp/support/status.h>

#include <string>
#include <unordered_map>

namespace mbstream {

enum class Role : unsigned {
  kSubmit = 1,  // SubmitModel
  kRun = 2,     // StartRun, CancelRun
  kView = 4,    // List*, Get*, WatchRun, Subscribe (viewers)
  kAdmin = 7,   // everything
};

class Authorizer {
 public:
  // No token file: every call is allowed (loopback and unix sockets; see the server's
  // warning for other addresses).
  static Authorizer AllowAll() { return Authorizer(); }
  // Reads a token file. Throws InputError naming the file and line for a malformed line or
  // an unknown role, and when the file has no token.
  static Authorizer FromTokenFile(const std::string& path);

  // OK, UNAUTHENTICATED (no or unknown token) or PERMISSION_DENIED (the token lacks `role`).
  // The scheme name "Bearer" is matched case-insensitively (RFC 6750 / RFC 7235).
  grpc::Status Check(const grpc::ServerContextBase& context, Role role) const;

  // Who calls: the id of the caller's token ("t-" and 12 hex digits of its SHA-256, safe to
  // store and log), "" without token checking or without a known token.
  std::string CallerId(const grpc::ServerContextBase& context) const;
  // Whether the caller's token has `role` (true without token checking).
  bool CallerHas(const grpc::ServerContextBase& context, Role role) const;

  bool enabled() const { return enabled_; }
  size_t token_count() const { return roles_.size(); }

 private:
  Authorizer() = default;
  struct Grant {
    unsigned roles = 0;  // role bits
    std::string id;      // the token's id (CallerId)
  };
  // The caller's grant, nullptr without a known token.
  const Grant* Find(const grpc::ServerContextBase& context) const;

  bool enabled_ = false;
  std::unordered_map<std::string, Grant> roles_;  // token -> grant
};

const char* RoleName(Role role);

}  // namespace mbstream
