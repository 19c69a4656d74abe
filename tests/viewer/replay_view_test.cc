// The viewer's side of a replay under an X display (a private Xvfb when none is set): the
// window's keys and time slider, driven with synthetic VTK events, become the replay's
// controls; the comparison's ghost is a translucent copy posed on its own.
#include <gtest/gtest.h>

#include <vtkCommand.h>
#include <vtkNew.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkSliderRepresentation.h>

#include <numbers>

#include "tests/viewer/script_test_util.h"
#include "tests/viewer/xvfb_display.h"
#include "viewer/kinematics/pose_solver.h"
#include "viewer/link/link_status.h"
#include "viewer/link/replay_keys.h"
#include "viewer/model/script_scene.h"
#include "viewer/scene/scene.h"

namespace mbstream::viewer {
namespace {

namespace ss = scene_script;

SceneDescription Irb1600() {
  const ss::Translation translation =
      ss::TranslateScriptFile(ss::testing::SourcePath("models/irb1600/irb1600.scene"));
  EXPECT_TRUE(translation.ok());
  return SceneFromScript(translation.script);
}

std::unique_ptr<Scene> MakeScene(double ghost_opacity) {
  if (!testing::EnsureDisplay()) return nullptr;
  SceneOptions options;
  options.width = 320;
  options.height = 240;
  options.offscreen = true;
  options.ghost_opacity = ghost_opacity;
  return std::make_unique<Scene>(Irb1600(), options);
}

// A key press as the window delivers it: the interactor's KeyPressEvent with its key sym.
void PressKey(vtkRenderWindowInteractor* interactor, const char* key_sym) {
  interactor->SetKeySym(key_sym);
  interactor->InvokeEvent(vtkCommand::KeyPressEvent, nullptr);
}

std::string Describe(const v1::ReplayControl& control) {
  switch (control.action_case()) {
    case v1::ReplayControl::kPause:
      return "pause";
    case v1::ReplayControl::kResume:
      return "resume";
    case v1::ReplayControl::kStep:
      return "step " + std::to_string(control.step());
    case v1::ReplayControl::kSeekSeq:
      return "seek " + std::to_string(control.seek_seq());
    default:
      return "other";
  }
}

TEST(ReplayViewTest, KeysAndSliderBecomeReplayControls) {
  std::unique_ptr<Scene> scene = MakeScene(0.0);
  if (!scene) GTEST_SKIP() << "no X display and no Xvfb";
  LinkStatus status;
  status.StartRun("r-1", "m-1", "IRB1600", 6);
  status.SetReplay(false, 1.0, 401, "", "ps-1");
  std::vector<std::string> sent;
  ReplayKeys keys(
      [&](const v1::ReplayControl& control) {
        sent.push_back(Describe(control));
        return true;
      },
      &status);
  vtkNew<vtkRenderWindowInteractor> interactor;
  interactor->SetRenderWindow(scene->render_window());
  interactor->Initialize();
  keys.Install(interactor);
  keys.Update();  // the slider appears: 0 .. 400

  PressKey(interactor, "space");
  status.SetReplay(true, 1.0, 401, "", "ps-1");  // the server's answer: paused
  PressKey(interactor, "Right");
  PressKey(interactor, "Left");
  PressKey(interactor, "space");
  PressKey(interactor, "x");  // not a replay key: left to the camera style
  EXPECT_EQ(sent, (std::vector<std::string>{"pause", "step 1", "step -1", "resume"}));

  auto* slider = static_cast<vtkSliderRepresentation*>(keys.slider()->GetRepresentation());
  EXPECT_TRUE(keys.slider()->GetEnabled());
  EXPECT_DOUBLE_EQ(slider->GetMaximumValue(), 400.0);
  status.SetSeq(123);
  keys.Update();
  EXPECT_DOUBLE_EQ(slider->GetValue(), 123.0);  // the slider follows the frame shown
  slider->SetValue(250.4);                      // the user drags it and lets go
  keys.slider()->InvokeEvent(vtkCommand::EndInteractionEvent, nullptr);
  EXPECT_EQ(sent.back(), "seek 250");
}

TEST(ReplayViewTest, GhostIsATranslucentCopyPosedOnItsOwn) {
  std::unique_ptr<Scene> scene = MakeScene(0.35);
  if (!scene) GTEST_SKIP() << "no X display and no Xvfb";
  GhostLayer* ghost = scene->ghost();
  ASSERT_NE(ghost, nullptr);
  EXPECT_EQ(ghost->actor_count(), scene->part_actor_count());
  EXPECT_DOUBLE_EQ(ghost->opacity(), 0.35);

  const std::vector<double> q = {0.1, -0.2, 0.3, 0.4, -0.5, 0.6};
  const std::vector<double> ghost_q = {0.2, 0.1, -0.3, 0.0, 0.5, -0.6};
  scene->SetJointValues(q);
  ghost->SetJointValues(ghost_q);
  const SceneDescription description = Irb1600();
  PoseSolver solver(description.chain, description.probes);
  Pose expected = solver.MakePose();
  solver.Solve(ghost_q, &expected);
  const std::vector<Eigen::Isometry3d> frames = ghost->Frames();
  ASSERT_EQ(frames.size(), expected.frames.size());
  for (size_t k = 0; k < frames.size(); ++k) {
    EXPECT_TRUE(frames[k].isApprox(expected.frames[k], 0.0)) << "frame " << k;  // bit for bit
  }
  scene->Render();  // both drawn
  EXPECT_EQ(scene->ProbeReports()[0].position_m, [&] {
    Pose own = solver.MakePose();
    solver.Solve(q, &own);
    return own.probes[0];
  }());  // the scene's own probes stay the run's

  std::unique_ptr<Scene> plain = MakeScene(0.0);
  EXPECT_EQ(plain->ghost(), nullptr);
}

}  // namespace
}  // namespace mbstream::viewer
