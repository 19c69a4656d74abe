// Who may watch on the web pages: a page's token is checked with the simulation server's
// view role (a ListRuns of one run with the page's token), so that the pages need what the
// server's own clients need, and the viewer keeps no token list of its own. Verdicts are
// cached for a minute per token; a server without tokens admits the empty token.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "net/client_channel.h"
#include "viewer/web/web_server.h"

namespace mbstream::viewer {

class PageAccess {
 public:
  // `security` as the viewer's link has it (its own token is not used for pages).
  PageAccess(const std::string& server_address, net::ClientSecurity security);
  // WebOptions::check_access: calls `done` once, on a gRPC thread (or at once from the cache).
  void Check(const std::string& token, std::function<void(WebOptions::Access)> done);
  struct State;

 private:
  std::shared_ptr<State> state_;  // shared with calls in flight
};

}  // namespace mbstream::viewer
