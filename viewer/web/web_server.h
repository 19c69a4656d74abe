// mbstream-viewer --web HOST:PORT: an HTTP server (Boost.Beast) for the browser page and its
// files, and a WebSocket per page that gets the scene once per model (scene_export.h), then
// the latest pose (frame_message.h). A page never queues: while its socket is busy, a newer
// frame replaces the one waiting, and the page counts the gap (each frame is numbered). The
// page's replay controls come back on its socket as small JSON messages.
//
// Limits, each refused or closed with a logged reason: request headers and bodies over 8 KiB,
// methods other than GET and HEAD, paths outside the page's files, more than `max_pages`
// sockets (HTTP 503), WebSocket messages over 4 KiB or not JSON controls, idle or stalled
// connections (Beast's server timeouts: 30 s for HTTP, pings for WebSockets).
//
// With `tls_cert_file`/`tls_key_file` (mbstream-viewer --web-tls CERT,KEY) everything is HTTPS
// and WSS (OpenSSL through Boost.Beast's ssl_stream); a plain-HTTP client fails the handshake.
// With `check_access`, a page's first WebSocket message must be {"token":"..."} (the page
// takes it from its URL fragment, which never reaches a server log, or asks for it); nothing
// is sent to the page until the check admits it, and a refused page gets
// {"type":"denied","status":401|403|503,"message":...} and a close (1008, policy).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>

namespace mbstream::viewer {

struct WebOptions {
  std::string address;         // HOST:PORT; port 0 = any free port
  std::filesystem::path root;  // the page: index.html, page.js, node_modules/three/
  int max_pages = 32;          // open WebSockets at once
  std::string tls_cert_file;   // PEM certificate chain; empty = plain HTTP
  std::string tls_key_file;    // its PEM private key

  // A page's verdict: status 0 admits it; 401 (no or unknown token), 403 (not allowed) or
  // 503 (could not check) refuse it with `message`. An admitted page with `controls` false
  // watches only: its replay controls are refused (logged, and the page told
  // {"type":"control_refused","message":...}), `message` saying why; the page learns it on
  // admission from {"type":"access","controls":BOOL,"message":...}.
  struct Access {
    int status = 0;
    std::string message;
    bool controls = true;
  };
  // Checks a page's token (maybe empty); calls `done` once, on any thread. Empty = every page
  // is admitted without a token message.
  std::function<void(const std::string& token, std::function<void(Access)> done)> check_access;
};

class WebServer {
 public:
  // A control a page sent, as JSON text ({"pause":true}, {"seek_seq":N}, ...); returns false
  // when it could not be passed on.
  using OnControl = std::function<bool(const std::string& json)>;

  // Binds and listens (no thread yet). Throws std::runtime_error naming the address and the
  // reason when it cannot, or when the page's files are not in `root`.
  WebServer(WebOptions options, OnControl on_control);
  ~WebServer();  // Stop()
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  // http://HOST:PORT/ (https:// with TLS) with the port bound.
  std::string url() const;
  // Serves on a thread of its own until Stop().
  void Start();
  void Stop();

  // Any thread: a new scene (sent to every page, and to every page that opens later), and
  // the newest frame (sent to every page, replacing one not yet sent).
  void SetScene(std::string json);
  void PublishFrame(std::string json);
  // Any thread: runs `task` on the server's thread (queued until Start, dropped at Stop).
  void Post(std::function<void()> task);

  int pages() const;
  struct Impl;

 private:
  std::shared_ptr<Impl> impl_;
};

}  // namespace mbstream::viewer
