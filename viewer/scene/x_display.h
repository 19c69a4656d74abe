// The viewer's one connection to the X server, held for the viewer's whole life.
//
// Its render window is put on this connection (vtkRenderWindow::SetDisplayId), so VTK never
// opens or closes one of its own. A window per run used to: the X server then had no client
// between two runs, and xvfb-run's Xvfb (started without -noreset) resets when its last
// client leaves; the next run's window, connecting during that reset, made VTK abort ("bad X
// server connection ... Aborting").
//
// A server that goes away (Xvfb killed) is noticed by Poll() or by any Xlib call on the
// connection. Xlib's fatal I/O error handler would end the process; here it only logs and
// marks the connection lost (XSetIOErrorExitHandler, libX11 1.8), and from then on nothing
// may talk to it: the owner stops drawing and never frees what lives on it. X protocol
// errors are logged, never fatal.
#pragma once

#include <atomic>
#include <string>

namespace mbstream::viewer {

class XDisplay {
 public:
  // Opens $DISPLAY; throws SceneError naming it when no X server answers there. At most one
  // XDisplay exists at a time (the error handlers are the process's).
  XDisplay();
  // Closes the connection (unless lost) and restores the previous error handlers.
  ~XDisplay();
  XDisplay(const XDisplay&) = delete;
  XDisplay& operator=(const XDisplay&) = delete;

  // The Xlib Display*, for vtkRenderWindow::SetDisplayId.
  void* handle() const { return display_; }
  const std::string& name() const { return name_; }
  // True once the X server went away (any thread may ask).
  bool lost() const { return lost_.load(); }

  // The thread that draws: reads what the server sent, without blocking, so that a server
  // that went away is noticed even when nothing is drawn to it (an offscreen window sends
  // nothing). `discard_events`: drops the events read (no interactor takes them). Returns
  // !lost().
  bool Poll(bool discard_events);

  // Called by the I/O error handler when `display` is this connection.
  void MarkLost(const char* why);

 private:
  void* display_ = nullptr;
  std::string name_;
  std::atomic<bool> lost_{false};
  void* previous_io_handler_ = nullptr;
  void* previous_error_handler_ = nullptr;
};

}  // namespace mbstream::viewer
