#include <spdlog/spdlog.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <optional>

#include "shared/common/check.h"
#include "viewer/app/commands.h"
#include "viewer/app/scene_loading.h"
#include "viewer/scene/scene.h"
#include "viewer/scene/scene_error.h"
#include "viewer/scene/view_window.h"

namespace mbstream::viewer {

namespace {

bool HasDisplay() {
  const char* display = std::getenv("DISPLAY");
  return display && *display;
}

}  // namespace

int RunPose(const PoseOptions& options) {
  std::optional<SceneDescription> description =
      LoadScene(options.scene_file, options.model_file, options.asset_dirs, options.package_paths,
                options.floating_base);
  if (!description) return 1;
  std::vector<double> q_si = description->initial_q;
  if (options.pose) {
    const std::optional<std::vector<double>> values = ParsePose(*options.pose);
    if (!values) return 1;
    try {
      q_si = ScriptUnitsToSi(description->chain, *values);
    } catch (const InputError& e) {
      std::cerr << "--pose: " << e.what() << "; give one value per joint (degrees or mm)\n";
      return 1;
    }
  }
  if (!HasDisplay()) {
    std::cerr << "no X display (DISPLAY is not set): run under Xvfb with --offscreen, e.g. "
                 "xvfb-run -a mbstream-viewer ... --offscreen --snapshot out.png\n";
    return 2;
  }
  SceneOptions scene_options;
  scene_options.width = options.width;
  scene_options.height = options.height;
  scene_options.offscreen = options.offscreen;
  scene_options.triangle_budget = options.triangle_budget;
  scene_options.window_title = "mbstream viewer: " + description->title;
  // The window on the viewer's own X connection: a DISPLAY where no server answers is said
  // here (exit 2), where VTK would abort.
  std::optional<ViewWindow> view;
  try {
    view.emplace(scene_options);
  } catch (const SceneError& e) {
    std::cerr << e.what() << "\n";
    return 2;
  }
  try {
    Scene scene(std::move(*description), scene_options, view->window());
    scene.SetJointValues(q_si);
    for (const ProbeReport& probe : scene.ProbeReports()) {
      auto clean = [](double v) { return std::abs(v) < 1e-12 ? 0.0 : v; };
      std::cout << "probe " << probe.name << ": (" << clean(probe.position_m.x()) << ", "
                << clean(probe.position_m.y()) << ", " << clean(probe.position_m.z()) << ") m in "
                << probe.frame << "\n";
    }
    if (options.snapshot) {
      scene.SnapshotPng(*options.snapshot);
      spdlog::info("snapshot written to {}", *options.snapshot);
    } else if (options.offscreen) {
      scene.Render();
    } else {
      scene.Interact();
    }
  } catch (const SceneError& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace mbstream::viewer
