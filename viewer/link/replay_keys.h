// The time controls of a replay in window mode: space pauses and resumes, Left and Right step
// one frame back and on, and a time slider (VTK's slider widget, along the top of the
// window) seeks to the frame under it when released. Each becomes a ReplayControl sent on
// the link's stream; the server answers with the replay's state, which the slider follows.
#pragma once

#include <functional>
#include <string>

#include <vtkRenderWindowInteractor.h>
#include <vtkSliderWidget.h>
#include <vtkSmartPointer.h>

#include "mbstream/v1/replay.pb.h"
#include "viewer/link/link_status.h"

namespace mbstream::viewer {

class ReplayKeys {
 public:
  using Send = std::function<bool(const v1::ReplayControl&)>;
  ReplayKeys(Send send, const LinkStatus* status);
  ~ReplayKeys();
  ReplayKeys(const ReplayKeys&) = delete;
  ReplayKeys& operator=(const ReplayKeys&) = delete;

  // Render thread: observes the interactor's key presses (before the camera style) and adds
  // the slider to its window.
  void Install(vtkRenderWindowInteractor* interactor);
  // Render thread, every draw: shows the slider once the run's frame count is known and moves
  // it to the frame shown (unless the user is dragging it).
  void Update();

  // What a key does ("space", "Left", "Right"); true when it was a replay key. Public for the
  // tests, which also drive it through the interactor's KeyPressEvent.
  bool OnKey(const std::string& key_sym);
  // The slider was released at `value` (a frame number): seek there.
  void OnSliderReleased(double value);
  vtkSliderWidget* slider() { return slider_; }

 private:
  Send send_;
  const LinkStatus* status_;
  vtkSmartPointer<vtkSliderWidget> slider_;
  vtkSmartPointer<vtkRenderWindowInteractor> interactor_;
  unsigned long key_observer_ = 0;
  bool dragging_ = false;
  bool enabled_ = false;
};

}  // namespace mbstream::viewer
