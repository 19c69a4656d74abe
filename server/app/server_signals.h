// How mbstream-server stops: SIGTERM drains (its runs get --grace-s to end), SIGINT stops
// at once (runs INTERRUPTED); a second signal, or 5 s after the shutdown began, exits
// without waiting for requests still being served.
#pragma once

#include <csignal>

#include "server/app/server_host.h"

namespace mbstream {

// Blocks SIGINT and SIGTERM in the calling thread and every thread it starts from now on
// (call first, before any thread), and returns them for ServeUntilSignalled.
sigset_t BlockStopSignals();

// Serves until `signals` arrive, then drains or shuts `host` down; returns when it stopped.
void ServeUntilSignalled(ServerHost& host, const sigset_t& signals);

}  // namespace mbstream
