#include "viewer/scene/view_window.h"

#include "viewer/scene/kept_for_good.h"

namespace mbstream::viewer {

ViewWindow::ViewWindow(const SceneOptions& options) : window_(MakeRenderWindow(options)) {
  window_->SetDisplayId(display_.handle());  // VTK opens no connection of its own
}

ViewWindow::~ViewWindow() {
  // On a lost display the window keeps its reference for good (see the header); then the
  // connection is left open too (XDisplay).
  if (display_.lost()) {
    window_->Register(nullptr);
    KeepForGood(window_.Get());
  }
}

}  // namespace mbstream::viewer
