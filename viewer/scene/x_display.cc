#include "viewer/scene/x_display.h"

#include <spdlog/spdlog.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "viewer/scene/kept_for_good.h"
#include "viewer/scene/scene_error.h"

// Last: Xlib's macros (None, Status, Bool...) would clash with the headers above.
#include <X11/Xlib.h>

namespace mbstream::viewer {

namespace {

std::atomic<XDisplay*> current_display{nullptr};
std::atomic<int> protocol_errors{0};
constexpr int kProtocolErrorsLogged = 20;

// Xlib calls this when a connection breaks. Returning is allowed since libX11 1.8, which
// then calls the display's exit handler (below), whose default would exit.
int OnIoError(Display* display) {
  const int error = errno;
  XDisplay* ours = current_display.load();
  // A read that found the connection closed leaves EAGAIN (the socket is non-blocking).
  const char* why =
      error != 0 && error != EAGAIN ? std::strerror(error) : "the server closed the connection";
  if (ours && ours->handle() == display) {
    ours->MarkLost(why);
  } else {
    spdlog::error("an X connection not the viewer's broke ({})", why);
  }
  return 0;
}

#ifdef MBSTREAM_HAVE_X_IO_ERROR_EXIT_HANDLER
// The display stays marked broken: later Xlib calls on it return at once.
void StayAfterIoError(Display*, void*) {}
#endif

int OnProtocolError(Display* display, XErrorEvent* event) {
  const int seen = ++protocol_errors;
  if (seen > kProtocolErrorsLogged) return 0;
  char text[256] = {};
  XGetErrorText(display, event->error_code, text, sizeof(text) - 1);
  spdlog::warn("X error {} ({}) on request {}.{}{}", static_cast<int>(event->error_code), text,
               static_cast<int>(event->request_code), static_cast<int>(event->minor_code),
               seen == kProtocolErrorsLogged ? "; further X errors are not logged" : "");
  return 0;
}

}  // namespace

XDisplay::XDisplay() {
  const char* name = std::getenv("DISPLAY");
  name_ = name ? name : "";
  Display* display = XOpenDisplay(nullptr);
  if (!display) {
    throw SceneError("no X server answers at DISPLAY='" + name_ +
                     "': start one (xvfb-run -a mbstream-viewer ... --offscreen) or set "
                     "DISPLAY to a running one");
  }
  display_ = display;
  XDisplay* expected = nullptr;
  if (!current_display.compare_exchange_strong(expected, this)) {
    XCloseDisplay(display);
    throw SceneError("a second X connection was asked for; the viewer keeps one");
  }
#ifdef MBSTREAM_HAVE_X_IO_ERROR_EXIT_HANDLER
  XSetIOErrorExitHandler(display, StayAfterIoError, nullptr);
#endif
  previous_io_handler_ = reinterpret_cast<void*>(XSetIOErrorHandler(OnIoError));
  previous_error_handler_ = reinterpret_cast<void*>(XSetErrorHandler(OnProtocolError));
}

XDisplay::~XDisplay() {
  XSetErrorHandler(reinterpret_cast<XErrorHandler>(previous_error_handler_));
  XSetIOErrorHandler(reinterpret_cast<XIOErrorHandler>(previous_io_handler_));
  // A lost connection is left alone: what lives on it may still point at it.
  if (lost()) {
    KeepForGood(display_);
  } else {
    XCloseDisplay(static_cast<Display*>(display_));
  }
  current_display = nullptr;
}

bool XDisplay::Poll(bool discard_events) {
  if (lost()) return false;
  auto* display = static_cast<Display*>(display_);
  if (!discard_events) {
    XPending(display);  // reads and queues what came; a broken connection calls OnIoError
    return !lost();
  }
  // Only while events are queued: XNextEvent on an empty queue would read, and block.
  while (XPending(display) > 0 && !lost()) {
    XEvent event;
    XNextEvent(display, &event);
  }
  return !lost();
}

void XDisplay::MarkLost(const char* why) {
  if (lost_.exchange(true)) return;
#ifdef MBSTREAM_HAVE_X_IO_ERROR_EXIT_HANDLER
  spdlog::error(
      "the X display {} is lost ({}): the viewer draws nothing from now on (no window, video "
      "frames or snapshots) and goes on answering probes",
      name_, why);
#else
  spdlog::error("the X display {} is lost ({}); this libX11 (before 1.8) ends the process", name_,
                why);
#endif
}

}  // namespace mbstream::viewer
