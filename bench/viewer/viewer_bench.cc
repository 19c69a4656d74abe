// Viewer timings on the shipped IRB 1600 scene (models/irb1600/irb1600.scene):
//  BM_ViewerFrame        what the viewer does per received frame besides drawing: joint values
//                        -> all link frames and probes (SetJointValues), the probe report
//                        (ProbeReports), and the actors' matrices (SyncActors). No render.
//  BM_ViewerRender/WxH   one offscreen frame with a new pose, to completion (glFinish);
//                        needs an X display: run under `xvfb-run -a`. Reports fps.
// On a generated PR2-sized model (bench/viewer/large_model.h: 41 links, 1M triangles of
// binary STL meshes, no third-party files):
//  BM_LoadMeshes/B       parse the URDF and every mesh (cache cleared) and build the Scene
//                        (decimation, pipelines, normals, camera) at 960x720; no render.
//  BM_RenderLargeModel/B one offscreen frame at 960x720 with a new pose of all 40 joints, to
//                        completion.
// B = SceneOptions::triangle_budget (0 = no decimation).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>

#include "bench/viewer/large_model.h"
#include "viewer/model/script_scene.h"
#include "viewer/model/urdf_scene.h"
#include "viewer/scene/mesh_cache.h"
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

bool HasDisplay(benchmark::State& state) {
  const char* display = std::getenv("DISPLAY");
  if (display && *display) return true;
  state.SkipWithError("no X display: run under xvfb-run -a");
  return false;
}

const bench::LargeModel& Large() {
  static const bench::LargeModel model = bench::WriteLargeModel(
      std::filesystem::temp_directory_path() / "mbstream_large_model", 4, 10, 1'000'000);
  return model;
}

std::unique_ptr<Scene> MakeLargeScene(long long triangle_budget) {
  SceneOptions options;
  options.width = 960;
  options.height = 720;
  options.offscreen = true;
  options.triangle_budget = triangle_budget;
  return std::make_unique<Scene>(SceneFromUrdfFile(Large().urdf), options);
}

void BM_LoadMeshes(benchmark::State& state) {
  if (!HasDisplay(state)) return;
  Large();
  long long triangles = 0;
  for (auto _ : state) {
    ClearMeshCache();
    std::unique_ptr<Scene> scene = MakeLargeScene(state.range(0));
    triangles = scene->triangle_count();
    state.PauseTiming();
    scene.reset();
    state.ResumeTiming();
  }
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["links"] = Large().links;
}
BENCHMARK(BM_LoadMeshes)
    ->Arg(0)
    ->Arg(SceneOptions::kDefaultTriangleBudget)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_RenderLargeModel(benchmark::State& state) {
  if (!HasDisplay(state)) return;
  ClearMeshCache();
  std::unique_ptr<Scene> scene = MakeLargeScene(state.range(0));
  std::vector<double> q(scene->dof());
  for (int i = 0; i < 5; ++i) scene->Render();  // warm up: shaders, buffers
  int frame = 0;
  for (auto _ : state) {
    const double s = std::sin(0.05 * frame++);
    for (size_t j = 0; j < q.size(); ++j) q[j] = 0.3 * s * ((j % 3) - 1.0);
    scene->SetJointValues(q);
    scene->Render();
    scene->render_window()->WaitForCompletion();
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["triangles"] = static_cast<double>(scene->triangle_count());
}
BENCHMARK(BM_RenderLargeModel)
    ->Arg(0)
    ->Arg(400'000)
    ->Arg(200'000)
    ->Arg(SceneOptions::kDefaultTriangleBudget)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace mbstream::viewer

BENCHMARK_MAIN();
