// Who may watch on the web pages: a page's token is checked with the simulation server's
// view role (a ListRuns of one run with the page's token), so that the pages need what the
// server's own clients need, and the viewer keeps no token list of its own. Verdicts are
// cached for a minute per token; a server without tokens admits the empty token.
//
// A replay's controls (pause, seek, speed, step) act on the one replay that the viewer's
// window and every page show, so an admitted page may steer it only when its token may also
// replay runs to everyone: the server's run role (that of ReplayRun, which streams a stored
// run to every follower). A view-only token watches; its page's controls are refused. The
// viewer's own token (view role is enough to subscribe) is never lent to a page.
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "shared/net/client_channel.h"
#include "viewer/web/web_server.h"

namespace mbstream::viewer {

class PageAccess {
 public:
  // `security` as the viewer's link has it (its own token is not used for pages).
  // `replay_controls`: the viewer replays a run (--run) and passes pages' controls on; else
  // no page has controls and only the view role is checked.
  PageAccess(const std::string& server_address, net::ClientSecurity security, bool replay_controls);
  // WebOptions::check_access: calls `done` once, on a gRPC thread (or at once from the cache).
  void Check(const std::string& token, std::function<void(WebOptions::Access)> done);
  struct State;

 private:
  std::shared_ptr<State> state_;  // shared with calls in flight
};

}  // namespace mbstream::viewer
