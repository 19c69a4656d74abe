// The viewer's one window on its one X connection (issue 36, item 9), each test on a private
// Xvfb of its own: scenes come and go in the same window without a second connection, and an
// X server that goes away is noticed, logged and survived; scenes are then built without a
// window, and their probes still answer.
#include <gtest/gtest.h>

#include <vtkRendererCollection.h>

#include <cstdlib>
#include <fstream>
#include <future>
#include <optional>
#include <sstream>
#include <thread>

#include "tests/viewer/script_test_util.h"
#include "tests/viewer/xvfb_server.h"
#include "viewer/link/scene_slot.h"
#include "viewer/model/script_scene.h"
#include "viewer/model/urdf_scene.h"
#include "viewer/scene/scene_error.h"
#include "viewer/scene/view_window.h"

namespace mbstream::viewer {
namespace {

namespace ss = scene_script;

SceneDescription Irb1600() {
  const ss::Translation translation =
      ss::TranslateScriptFile(ss::testing::SourcePath("models/irb1600/irb1600.scene"));
  EXPECT_TRUE(translation.ok());
  return SceneFromScript(translation.script);
}

SceneDescription Pendulum() {
  return SceneFromUrdfFile(ss::testing::SourcePath("models/pendulum/single_pendulum.urdf"));
}

SceneOptions Small() {
  SceneOptions options;
  options.width = 160;
  options.height = 120;
  options.offscreen = true;
  return options;
}

// DISPLAY set to `display` while it lives (XDisplay opens $DISPLAY).
class ScopedDisplay {
 public:
  explicit ScopedDisplay(const std::string& display) {
    if (const char* old = std::getenv("DISPLAY")) old_ = old;
    setenv("DISPLAY", display.c_str(), 1);
  }
  ~ScopedDisplay() {
    if (old_) {
      setenv("DISPLAY", old_->c_str(), 1);
    } else {
      unsetenv("DISPLAY");
    }
  }

 private:
  std::optional<std::string> old_;
};

// Client connections the X server of `display` (":N") has accepted: its connected sockets
// bound to /tmp/.X11-unix/XN (abstract or not), from /proc/net/unix.
int XClients(const std::string& display) {
  const std::string path = "/tmp/.X11-unix/X" + display.substr(1);
  std::ifstream table("/proc/net/unix");
  std::string line;
  int clients = 0;
  std::getline(table, line);  // header
  while (std::getline(table, line)) {
    std::istringstream fields(line);
    std::string slot, refs, protocol, flags, type, state, inode, name;
    fields >> slot >> refs >> protocol >> flags >> type >> state >> inode >> name;
    const bool ours = name == path || name == "@" + path;
    if (ours && state == "03") ++clients;  // SS_CONNECTED; the listening ones are 01
  }
  return clients;
}

int Differing(const RgbImage& a, const RgbImage& b) {
  int differing = 0;
  for (size_t i = 0; i < a.rgb.size() && i < b.rgb.size(); ++i) differing += a.rgb[i] != b.rgb[i];
  return differing;
}

// Poses the slot's scene at q = 0 and q = 0.5 (every joint), as the link does: true when its
// one probe answers both and moves between them.
bool ProbeMoves(SceneSlot* slot) {
  std::vector<ProbeReport> at_zero, at_half;
  const bool posed = slot->WithScene([&](Scene& scene) {
    scene.SetJointValues(std::vector<double>(scene.dof(), 0.0));
    scene.ProbeReports(&at_zero);
    scene.SetJointValues(std::vector<double>(scene.dof(), 0.5));
    scene.ProbeReports(&at_half);
  });
  return posed && at_zero.size() == 1 && at_half.size() == 1 &&
         (at_zero[0].position_m - at_half[0].position_m).norm() > 1e-3;
}

TEST(ViewWindowTest, ScenesComeAndGoInOneWindowOnOneConnection) {
  testing::XvfbServer xvfb;
  ASSERT_TRUE(xvfb.Start()) << "Xvfb does not start (Debian package xvfb)";
  const ScopedDisplay display(xvfb.display());
  ASSERT_EQ(XClients(xvfb.display()), 0);
  ViewWindow view(Small());
  vtkRenderWindow* window = view.window();
  ASSERT_NE(window, nullptr);
  EXPECT_EQ(XClients(xvfb.display()), 1);

  std::optional<RgbImage> previous;
  std::unique_ptr<Scene> scene;
  for (int run = 0; run < 6; ++run) {
    // As SceneSlot does: the next run's scene is built, then the last one goes.
    auto next = std::make_unique<Scene>(run % 2 == 0 ? Irb1600() : Pendulum(), Small(), window);
    scene = std::move(next);
    ASSERT_EQ(scene->render_window(), window);
    EXPECT_EQ(window->GetRenderers()->GetNumberOfItems(), 1) << "run " << run;
    const RgbImage image = scene->Capture();
    EXPECT_EQ(image.width, 160);
    EXPECT_EQ(image.height, 120);
    if (previous) {
      EXPECT_GT(Differing(image, *previous), 100) << "run " << run << " shows no change";
    }
    previous = image;
    EXPECT_EQ(XClients(xvfb.display()), 1) << "run " << run << " opened an X connection";
    EXPECT_TRUE(view.Check(true));
  }
  scene.reset();
  EXPECT_EQ(window->GetRenderers()->GetNumberOfItems(), 0);
  EXPECT_EQ(XClients(xvfb.display()), 1);
}

TEST(ViewWindowTest, NoXServerIsAnErrorNamingTheDisplay) {
  testing::XvfbServer xvfb;
  ASSERT_TRUE(xvfb.Start());
  const std::string gone = xvfb.display();
  xvfb.Stop();
  const ScopedDisplay display(gone);
  try {
    ViewWindow view(Small());
    FAIL() << "a window on a display with no server";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("DISPLAY='" + gone + "'"), std::string::npos) << e.what();
  }
}

// The X server is killed under a drawing viewer: the process lives on (Xlib would have ended
// it), the display is reported lost, the scene shown lets go of the window, and the next
// run's scene is built without one; both answer probes.
TEST(ViewWindowTest, ALostDisplayIsSurvivedAndScenesGoOnWithoutAWindow) {
  testing::XvfbServer xvfb;
  ASSERT_TRUE(xvfb.Start());
  const ScopedDisplay display(xvfb.display());
  ViewWindow view(Small());
  SceneSlot slot(Small());

  // The render thread's part of SceneSlot::Replace (which waits on another thread).
  auto show = [&](SceneDescription description, vtkRenderWindow* window) {
    auto replaced = std::async(std::launch::async, [&slot, d = std::move(description)]() mutable {
      return slot.Replace(std::move(d));
    });
    Scene* scene = nullptr;
    for (bool changed = false; !changed;) {
      scene = slot.Service(window, &changed);
      if (!changed) std::this_thread::yield();
    }
    EXPECT_EQ(replaced.get(), "");
    return scene;
  };
  Scene* scene = show(Irb1600(), view.window());
  ASSERT_NE(scene->render_window(), nullptr);
  EXPECT_EQ(scene->Capture().width, 160);

  xvfb.Kill();  // returns once Xvfb has exited: our connection is closed at its end
  EXPECT_FALSE(view.Check(true));
  EXPECT_TRUE(view.lost());
  EXPECT_EQ(view.window(), nullptr);

  bool changed = true;
  EXPECT_EQ(slot.Service(view.window(), &changed), scene);
  EXPECT_FALSE(changed);
  EXPECT_EQ(scene->render_window(), nullptr);
  scene->Render();  // draws nothing, talks to no one
  EXPECT_THROW(scene->Capture(), SceneError);
  EXPECT_TRUE(ProbeMoves(&slot));

  Scene* next = show(Pendulum(), view.window());
  EXPECT_EQ(next->render_window(), nullptr);
  next->Render();
  EXPECT_THROW(next->SnapshotPngBytes(), SceneError);
  EXPECT_TRUE(ProbeMoves(&slot));
  slot.Shutdown();
  slot.DestroyScene();
}

}  // namespace
}  // namespace mbstream::viewer
