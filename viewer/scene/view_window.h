// The viewer's one render window, on its one X connection (x_display.h), for the viewer's
// whole life. Each run's Scene draws into it with a renderer of its own (Scene's constructor
// with a window), so that a new run changes what is drawn, never the window or the
// connection.
//
// Once the X server has gone away the window is no longer handed out (window() is null):
// scenes are then built without one, and the window and what was drawn in it are never
// freed, since freeing them would talk to a server that is not there.
#pragma once

#include <vtkRenderWindow.h>
#include <vtkSmartPointer.h>

#include "viewer/scene/scene.h"
#include "viewer/scene/x_display.h"

namespace mbstream::viewer {

class ViewWindow {
 public:
  // Opens the X connection ($DISPLAY) and makes the window with the options' size,
  // offscreen flag and title; the X server sees the window at the first render. Throws
  // SceneError naming DISPLAY when no X server answers.
  explicit ViewWindow(const SceneOptions& options);
  ~ViewWindow();
  ViewWindow(const ViewWindow&) = delete;
  ViewWindow& operator=(const ViewWindow&) = delete;

  // The window to draw into, or nullptr once the display is lost.
  vtkRenderWindow* window() { return display_.lost() ? nullptr : window_.Get(); }
  bool lost() const { return display_.lost(); }
  // The drawing thread, once per tick: notices a display that went away (XDisplay::Poll);
  // `discard_events` when no interactor reads the window's events. Returns !lost().
  bool Check(bool discard_events) { return display_.Poll(discard_events); }

 private:
  XDisplay display_;
  vtkSmartPointer<vtkRenderWindow> window_;
};

}  // namespace mbstream::viewer
