#include "viewer/link/replay_keys.h"

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkProperty2D.h>
#include <vtkSliderRepresentation2D.h>
#include <vtkTextProperty.h>

#include <cmath>

namespace mbstream::viewer {

namespace {

// Calls `function(keys, caller)` for an observed event.
template <typename Function>
vtkSmartPointer<vtkCallbackCommand> Callback(ReplayKeys* keys, Function function) {
  auto command = vtkSmartPointer<vtkCallbackCommand>::New();
  command->SetClientData(new std::pair<ReplayKeys*, Function>(keys, function));
  command->SetClientDataDeleteCallback(
      [](void* data) { delete static_cast<std::pair<ReplayKeys*, Function>*>(data); });
  command->SetCallback([](vtkObject* caller, unsigned long, void* client, void*) {
    auto* bound = static_cast<std::pair<ReplayKeys*, Function>*>(client);
    bound->second(bound->first, caller);
  });
  return command;
}

}  // namespace

ReplayKeys::ReplayKeys(Send send, const LinkStatus* status)
    : send_(std::move(send)), status_(status) {}

ReplayKeys::~ReplayKeys() {
  if (interactor_ && key_observer_) interactor_->RemoveObserver(key_observer_);
  if (slider_) slider_->EnabledOff();
}

void ReplayKeys::Install(vtkRenderWindowInteractor* interactor) {
  interactor_ = interactor;
  // Priority above the interactor style's, so that its own keys never see ours.
  auto on_key = Callback(this, [](ReplayKeys* keys, vtkObject* caller) {
    auto* source = static_cast<vtkRenderWindowInteractor*>(caller);
    const char* sym = source->GetKeySym();
    if (sym && keys->OnKey(sym)) {
      source->SetKeySym("");  // handled: the camera style ignores an empty key
      source->SetKeyCode('\0');
    }
  });
  key_observer_ = interactor->AddObserver(vtkCommand::KeyPressEvent, on_key, 10.0);

  auto representation = vtkSmartPointer<vtkSliderRepresentation2D>::New();
  representation->SetMinimumValue(0.0);
  representation->SetMaximumValue(1.0);
  representation->SetValue(0.0);
  representation->SetTitleText("frame");
  representation->GetPoint1Coordinate()->SetCoordinateSystemToNormalizedDisplay();
  representation->GetPoint1Coordinate()->SetValue(0.25, 0.94);
  representation->GetPoint2Coordinate()->SetCoordinateSystemToNormalizedDisplay();
  representation->GetPoint2Coordinate()->SetValue(0.95, 0.94);
  representation->SetSliderLength(0.015);
  representation->SetSliderWidth(0.03);
  representation->SetTubeWidth(0.006);
  representation->SetLabelFormat("%.0f");
  representation->GetTitleProperty()->SetFontSize(12);
  slider_ = vtkSmartPointer<vtkSliderWidget>::New();
  slider_->SetInteractor(interactor);
  slider_->SetRepresentation(representation);
  slider_->SetAnimationModeToJump();
  slider_->AddObserver(
      vtkCommand::StartInteractionEvent,
      Callback(this, [](ReplayKeys* keys, vtkObject*) { keys->dragging_ = true; }));
  slider_->AddObserver(
      vtkCommand::EndInteractionEvent, Callback(this, [](ReplayKeys* keys, vtkObject* caller) {
        auto* widget = static_cast<vtkSliderWidget*>(caller);
        keys->OnSliderReleased(
            static_cast<vtkSliderRepresentation*>(widget->GetRepresentation())->GetValue());
      }));
}

void ReplayKeys::Update() {
  if (!slider_) return;
  const v1::ViewerStatus status = status_->Get();
  if (status.mode() != "replay" || status.run_frames() < 2) return;
  auto* representation = static_cast<vtkSliderRepresentation*>(slider_->GetRepresentation());
  if (!enabled_) {
    representation->SetMaximumValue(static_cast<double>(status.run_frames() - 1));
    slider_->EnabledOn();
    enabled_ = true;
  }
  if (!dragging_ && status.seq() >= 0) representation->SetValue(static_cast<double>(status.seq()));
}

bool ReplayKeys::OnKey(const std::string& key_sym) {
  v1::ReplayControl control;
  if (key_sym == "space") {
    if (status_->Get().paused()) {
      control.set_resume(true);
    } else {
      control.set_pause(true);
    }
  } else if (key_sym == "Left") {
    control.set_step(-1);
  } else if (key_sym == "Right") {
    control.set_step(1);
  } else {
    return false;
  }
  send_(control);
  return true;
}

void ReplayKeys::OnSliderReleased(double value) {
  dragging_ = false;
  v1::ReplayControl control;
  control.set_seek_seq(static_cast<int64_t>(std::llround(std::max(0.0, value))));
  send_(control);
}

}  // namespace mbstream::viewer
