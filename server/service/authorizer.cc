#include "server/service/authorizer.h"

#include <fstream>
#include <sstream>

#include "server/common/check.h"

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

}  // namespace

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
    authorizer.roles_[token] |= bits;
  }
  if (authorizer.roles_.empty()) {
    throw InputError("the token file " + path + " has no token; add lines `<token> <role>`");
  }
  return authorizer;
}

grpc::Status Authorizer::Check(const grpc::ServerContext& context, Role role) const {
  if (!enabled_) return grpc::Status::OK;
  const auto& metadata = context.client_metadata();
  const auto found = metadata.find("authorization");
  static const std::string kBearer = "Bearer ";
  if (found == metadata.end() || found->second.size() <= kBearer.size() ||
      std::string(found->second.data(), kBearer.size()) != kBearer) {
    return grpc::Status(grpc::StatusCode::UNAUTHENTICATED,
                        "this server needs a token: send `authorization: Bearer <token>` "
                        "(mbstream --token-file FILE)");
  }
  const std::string token(found->second.data() + kBearer.size(),
                          found->second.size() - kBearer.size());
  const auto entry = roles_.find(token);
  if (entry == roles_.end()) {
    return grpc::Status(grpc::StatusCode::UNAUTHENTICATED,
                        "the token is not known to this server; check the token file");
  }
  const unsigned needed = static_cast<unsigned>(role);
  if ((entry->second & needed) != needed) {
    return grpc::Status(grpc::StatusCode::PERMISSION_DENIED,
                        std::string("the token lacks the role '") + RoleName(role) +
                            "' this call needs; ask the operator for a token with it");
  }
  return grpc::Status::OK;
}

}  // namespace mbstream
