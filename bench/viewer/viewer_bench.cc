// Viewer timings on the shipped IRB 1600 scene (models/irb1600/irb1600.scene):
//  BM_ViewerFrame        what the viewer does per received frame besides drawing: joint values
//                        -> all link frames and probes (SetJointValues), the probe report
//                        (ProbeReports), and the actors' matrices (SyncActors). No render.
//  BM_ViewerRender/WxH   one offscreen frame with a new pose, to completion (glFinish);
//                        needs an X display: run under `xvfb-run -a`. Reports fps.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <memory>

#include "viewer/model/script_scene.h"
#include "viewer/scene/scene.h"
#include "viewer/script/translator.h"

namespace mbstream::viewer {
namespace {

std::unique_ptr<Scene> MakeScene(int width, int height) {
  const scene_script::Translation translation = scene_script::TranslateScriptFile(
      std::string(MBSTREAM_SOURCE_DIR) + "/models/irb1600/irb1600.scene");
  if (!translation.ok()) return nullptr;
  SceneOptions options;
  options.width = width;
  options.height = height;
  options.offscreen = true;
  return std::make_unique<Scene>(SceneFromScript(translation.script), options);
}

// The seed motion q_i(t) = a_i sin(w0 t), sampled every 50 ms.
void SeedPose(int frame, std::vector<double>* q) {
  static const double a[6] = {M_PI, M_PI / 3, 0.25 * M_PI, M_PI, 0.6 * M_PI, M_PI};
  const double s = std::sin(M_PI / 10 * 0.05 * frame);
  for (int i = 0; i < 6; ++i) (*q)[i] = a[i] * s;
}

void BM_ViewerFrame(benchmark::State& state) {
  std::unique_ptr<Scene> scene = MakeScene(640, 480);
  if (!scene) {
    state.SkipWithError("the IRB 1600 scene does not translate");
    return;
  }
  std::vector<double> q(6);
  std::vector<ProbeReport> reports;
  int frame = 0;
  for (auto _ : state) {
    SeedPose(frame++, &q);
    scene->SetJointValues(q);
    scene->ProbeReports(&reports);
    scene->SyncActors();
    benchmark::DoNotOptimize(reports.data());
  }
}
BENCHMARK(BM_ViewerFrame);

void BM_ViewerRender(benchmark::State& state) {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display) {
    state.SkipWithError("no X display: run under xvfb-run -a");
    return;
  }
  const int width = static_cast<int>(state.range(0));
  const int height = static_cast<int>(state.range(1));
  std::unique_ptr<Scene> scene = MakeScene(width, height);
  if (!scene) {
    state.SkipWithError("the IRB 1600 scene does not translate");
    return;
  }
  std::vector<double> q(6);
  int frame = 0;
  for (int i = 0; i < 10; ++i) scene->Render();  // warm up: shaders, buffers
  for (auto _ : state) {
    SeedPose(frame++, &q);
    scene->SetJointValues(q);
    scene->Render();
    scene->render_window()->WaitForCompletion();
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ViewerRender)->Args({640, 480})->Args({1280, 720})->UseRealTime();

}  // namespace
}  // namespace mbstream::viewer

BENCHMARK_MAIN();
