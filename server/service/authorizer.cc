#include "server/service/authorizer.h"

#include <openssl/sha.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string_view>

#include "server/service/rpc_roles.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

bool ParseRole(const std::string& name, unsigned* bits) {
  if (name == "submit")
    *bits |= static_cast<unsigned>(Role::kSubmit);
  else if (name == "run")
    *bits |= static_cast<unsigned>(Role::kRun);
  else if (name == "view")
    *bits |= static_cast<unsigned>(Role::kView);
  else if (name == "admin")
    *bits |= static_cast<unsigned>(Role::kAdmin);
  else
    return false;
  return true;
}

std::string TokenId(const std::string& token) {
  unsigned char digest[SHA256_DIGEST_LENGTH];
  SHA256(reinterpret_cast<const unsigned char*>(token.data()), token.size(), digest);
  std::string id = "t-";
  char hex[3];
  for (int i = 0; i < 6; ++i) {
    std::snprintf(hex, sizeof(hex), "%02x", digest[i]);
    id += hex;
  }
  return id;
}

// The token of an `authorization: Bearer <token>` value (scheme case-insensitive), or "".
std::string BearerToken(std::string_view value) {
  constexpr std::string_view kScheme = "bearer ";
  if (value.size() <= kScheme.size()) return "";
  const bool match = std::equal(kScheme.begin(), kScheme.end(), value.begin(), [](char a, char b) {
    return a == std::tolower(static_cast<unsigned char>(b));
  });
  return match ? std::string(value.substr(kScheme.size())) : "";
}

}  // namespace

Role RoleOf(std::string_view method) {
  for (const RpcRole& entry : kRpcRoles) {
    if (entry.method == method) return entry.role;
  }
  throw InternalError("RPC '" + std::string(method) + "' has no role in kRpcRoles");
}

const char* RoleName(Role role) {
  switch (role) {
    case Role::kSubmit:
      return "submit";
    case Role::kRun:
      return "run";
    case Role::kView:
      return "view";
    case Role::kAdmin:
      return "admin";
  }
  return "unknown";
}

Authorizer Authorizer::FromTokenFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot read the token file " + path + ": check the path");
  Authorizer authorizer;
  authorizer.enabled_ = true;
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    std::istringstream words(line);
    std::string token, roles, extra;
    if (!(words >> token) || token[0] == '#') continue;
    const std::string where = path + ":" + std::to_string(number) + ": ";
    if (!(words >> roles) || (words >> extra)) {
      throw InputError(where +
                       "expected `<token> <role>[,<role>...]` (roles: submit, run, "
                       "view, admin)");
    }
    unsigned bits = 0;
    std::istringstream list(roles);
    for (std::string role; std::getline(list, role, ',');) {
      if (!ParseRole(role, &bits)) {
        throw InputError(where + "unknown role '" + role + "'; use submit, run, view or admin");
      }
    }
    if (token.size() < 16) {
      throw InputError(where +
                       "the token is shorter than 16 characters; use a long random "
                       "one (e.g. `openssl rand -hex 32`)");
    }
    Authorizer::Grant& grant = authorizer.roles_[token];
    grant.roles |= bits;
    grant.id = TokenId(token);
  }
  if (authorizer.roles_.empty()) {
    throw InputError("the token file " + path + " has no token; add lines `<token> <role>`");
  }
  return authorizer;
}

const Authorizer::Grant* Authorizer::Find(const grpc::ServerContextBase& context) const {
  const auto& metadata = context.client_metadata();
  const auto found = metadata.find("authorization");
  if (found == metadata.end()) return nullptr;
  const std::string token =
      BearerToken(std::string_view(found->second.data(), found->second.size()));
  const auto entry = token.empty() ? roles_.end() : roles_.find(token);
  return entry == roles_.end() ? nullptr : &entry->second;
}

grpc::Status Authorizer::Check(const grpc::ServerContextBase& context, Role role) const {
  if (!enabled_) return grpc::Status::OK;
  const auto& metadata = context.client_metadata();
  const auto found = metadata.find("authorization");
  if (found == metadata.end() ||
      BearerToken(std::string_view(found->second.data(), found->second.size())).empty()) {
    return grpc::Status(grpc::StatusCode::UNAUTHENTICATED,
                        "this server needs a token: send `authorization: Bearer <token>` "
                        "(mbstream --token-file FILE)");
  }
  const Grant* grant = Find(context);
  if (!grant) {
    return grpc::Status(grpc::StatusCode::UNAUTHENTICATED,
                        "the token is not known to this server; check the token file");
  }
  const unsigned needed = static_cast<unsigned>(role);
  if ((grant->roles & needed) != needed) {
    return grpc::Status(grpc::StatusCode::PERMISSION_DENIED,
                        std::string("the token lacks the role '") + RoleName(role) +
                            "' this call needs; ask the operator for a token with it");
  }
  return grpc::Status::OK;
}

std::string Authorizer::CallerId(const grpc::ServerContextBase& context) const {
  const Grant* grant = enabled_ ? Find(context) : nullptr;
  return grant ? grant->id : "";
}

bool Authorizer::CallerHas(const grpc::ServerContextBase& context, Role role) const {
  if (!enabled_) return true;
  const Grant* grant = Find(context);
  const unsigned needed = static_cast<unsigned>(role);
  return grant && (grant->roles & needed) == needed;
}

}  // namespace mbstream
