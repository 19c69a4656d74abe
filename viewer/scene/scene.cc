#include "viewer/scene/scene.h"

#include <spdlog/spdlog.h>
#include <vtkCoordinate.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkSphereSource.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>

#include "viewer/scene/camera_rig.h"
#include "viewer/scene/image_capture.h"
#include "viewer/scene/kept_for_good.h"
#include "viewer/scene/mesh_cache.h"
#include "viewer/scene/scene_error.h"
#include "viewer/scene/visual_pipeline.h"

namespace mbstream::viewer {

namespace {

vtkSmartPointer<vtkActor> MakeProbeActor(double radius) {
  vtkNew<vtkSphereSource> sphere;
  sphere->SetRadius(radius);
  sphere->SetThetaResolution(16);
  sphere->SetPhiResolution(12);
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(sphere->GetOutputPort());
  mapper->StaticOn();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(1.0, 0.9, 0.1);
  actor->GetProperty()->SetAmbient(0.6);  // a small yellow light, as in the seed
  actor->GetProperty()->SetDiffuse(0.6);
  return actor;
}

}  // namespace

vtkSmartPointer<vtkRenderWindow> MakeRenderWindow(const SceneOptions& options) {
  auto window = vtkSmartPointer<vtkRenderWindow>::New();
  window->SetMultiSamples(0);  // 4x cheaper under Mesa's software rasteriser
  window->SetOffScreenRendering(options.offscreen ? 1 : 0);
  window->SetSize(options.width, options.height);
  window->SetWindowName(options.window_title.c_str());
  return window;
}

Scene::Scene(SceneDescription description, SceneOptions options)
    : Scene(std::move(description), options, MakeRenderWindow(options), true) {}

Scene::Scene(SceneDescription description, SceneOptions options, vtkRenderWindow* window)
    : Scene(std::move(description), options, window, false) {}

Scene::Scene(SceneDescription description, const SceneOptions& options,
             vtkSmartPointer<vtkRenderWindow> window, bool owns_window)
    : description_(std::move(description)),
      solver_(description_.chain, description_.probes),
      pose_(solver_.MakePose()),
      render_pose_(solver_.MakePose()),
      owns_window_(owns_window) {
  if (!description_.initial_q.empty()) solver_.Solve(description_.initial_q, &pose_);
  version_ = 1;

  renderer_ = vtkSmartPointer<vtkRenderer>::New();
  renderer_->SetBackground(0.16, 0.18, 0.22);
  renderer_->SetBackground2(0.52, 0.57, 0.65);
  renderer_->GradientBackgroundOn();

  for (int k = 0; k < solver_.chain().frame_count(); ++k) {
    frame_matrices_.push_back(vtkSmartPointer<vtkMatrix4x4>::New());
  }
  const std::vector<long long> shares = TriangleShares(options.triangle_budget);
  bool textured = false;
  for (size_t i = 0; i < description_.visuals.size(); ++i) {
    const VisualPart& part = description_.visuals[i];
    try {
      AddPart(part, shares[i], &textured);
    } catch (const SceneError& e) {
      if (!part.fallback) throw;
      spdlog::warn("scene '{}': {}; drawing a placeholder for '{}'", description_.title, e.what(),
                   part.name);
      AddPart(*part.fallback, 0, &textured);
      missing_meshes_.push_back({part.fallback->mesh_filename, true});
      continue;
    }
    if (part.placeholder) missing_meshes_.push_back({part.mesh_filename, false});
  }
  AddMissingMeshesLine();
  if (textured) {
    spdlog::info(
        "scene '{}': some of its meshes' textures cannot be drawn (embedded in the file, "
        "not found beside it, or without texture coordinates); those surfaces are shown in "
        "their materials' colours",
        description_.title);
  }
  const double marker = description_.scene_box_m ? 0.012 * *description_.scene_box_m : 0.015;
  for (size_t i = 0; i < description_.probes.size(); ++i) {
    probe_actors_.push_back(MakeProbeActor(marker));
    renderer_->AddActor(probe_actors_.back());
  }
  if (options.contacts) {
    contacts_ = std::make_unique<ContactLayer>(renderer_, options.contact_scale);
  }
  if (options.ghost_opacity > 0.0) {
    ghost_ = std::make_unique<GhostLayer>(description_, renderer_, options.ghost_opacity);
  }
  SyncActors();

  double bounds[6];
  renderer_->ComputeVisiblePropBounds(bounds);
  const Eigen::Isometry3d& base = render_pose_.frames[0];
  if (description_.scene_box_m) {
    PlaceCamera(renderer_, CameraSphereOf(description_, base, bounds), base);
  } else {
    FrameBox(renderer_, bounds, base, static_cast<double>(options.width) / options.height);
  }
  AddLights(renderer_);
  // Last: nothing may throw once a shared window holds the renderer.
  if (window) {
    window_ = std::move(window);
    window_->AddRenderer(renderer_);
  }
}

Scene::~Scene() {
  if (window_ && !owns_window_) window_->RemoveRenderer(renderer_);
}

void Scene::ForgetWindow() {
  if (!window_) return;
  renderer_->Register(nullptr);  // kept for good, with its actors and the window it names
  KeepForGood(renderer_.Get());
  window_->Register(nullptr);
  KeepForGood(window_.Get());
  window_ = nullptr;
}

void Scene::RequireWindow() const {
  if (!window_) {
    throw SceneError(
        "the scene has no window to read (the X display is lost); the viewer "
        "answers probes but draws nothing until it is restarted");
  }
}

std::vector<long long> Scene::TriangleShares(long long budget) const {
  std::vector<long long> counts(description_.visuals.size(), 0);
  long long total = 0;
  for (size_t i = 0; i < counts.size(); ++i) {
    const auto* file = std::get_if<MeshFile>(&description_.visuals[i].geometry);
    if (!file) continue;
    try {
      counts[i] = CachedMeshFile(file->path)->triangle_count;
    } catch (const SceneError&) {
      // drawn by its fallback, or reported when its actors are made
    }
    total += counts[i];
  }
  std::vector<long long> shares(counts.size(), 0);
  if (budget <= 0 || total <= budget) return shares;
  for (size_t i = 0; i < counts.size(); ++i) {
    shares[i] = std::max<long long>(
        1, static_cast<long long>(static_cast<double>(counts[i]) * static_cast<double>(budget) /
                                  static_cast<double>(total)));
  }
  spdlog::info("scene '{}': {} triangles in its meshes, decimated to about {} on load",
               description_.title, total, budget);
  return shares;
}

void Scene::AddPart(const VisualPart& part, long long max_triangles, bool* textured) {
  VisualActors made = MakeVisualActors(part, max_triangles);
  for (const vtkSmartPointer<vtkActor>& actor : made.actors) {
    if (part.frame != kWorldFrame) actor->SetUserMatrix(frame_matrices_.at(part.frame));
    renderer_->AddActor(actor);
    part_actors_.push_back(actor);
    part_frames_.push_back(part.frame);
  }
  triangle_count_ += made.triangles;
  *textured = *textured || made.textured;
}

void Scene::AddMissingMeshesLine() {
  const std::string line = missing_meshes_line();
  if (line.empty()) return;
  missing_meshes_actor_ = vtkSmartPointer<vtkTextActor>::New();
  missing_meshes_actor_->SetInput(line.c_str());
  vtkTextProperty* text = missing_meshes_actor_->GetTextProperty();
  text->SetFontSize(14);
  text->SetColor(kPlaceholderColour.x(), kPlaceholderColour.y(), kPlaceholderColour.z());
  text->SetVerticalJustificationToTop();
  // Top left, clear of the run's HUD (bottom left): follows the window's size.
  missing_meshes_actor_->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  missing_meshes_actor_->SetPosition(0.01, 0.98);
  renderer_->AddActor2D(missing_meshes_actor_);
}

std::string MissingMeshesLine(const std::vector<MissingMesh>& missing, int shown) {
  std::vector<std::string> names;
  for (const MissingMesh& mesh : missing) {
    std::string name = mesh.filename;
    const std::size_t slash = name.find_last_of("/\\");
    if (slash != std::string::npos) name = name.substr(slash + 1);
    if (name.empty()) name = "(no file name)";
    if (mesh.unreadable) name += " (unreadable)";
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  if (names.empty()) return "";
  std::string line =
      std::to_string(names.size()) + (names.size() == 1 ? " mesh" : " meshes") + " missing: ";
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (static_cast<int>(i) == shown) {
      line += " and " + std::to_string(names.size() - i) + " more";
      break;
    }
    if (i > 0) line += ", ";
    line += names[i];
  }
  return line;
}

void Scene::SetJointValues(std::span<const double> q_si) {
  const std::lock_guard<std::mutex> lock(mutex_);
  solver_.Solve(q_si, &pose_);
  ++version_;
}

std::vector<ProbeReport> Scene::ProbeReports() const {
  std::vector<ProbeReport> reports;
  ProbeReports(&reports);
  return reports;
}

void Scene::ProbeReports(std::vector<ProbeReport>* out) const {
  const std::vector<ProbePoint>& probes = solver_.probes();
  out->resize(probes.size());
  const std::lock_guard<std::mutex> lock(mutex_);
  for (size_t i = 0; i < probes.size(); ++i) {
    ProbeReport& report = (*out)[i];
    if (report.name != probes[i].name) report.name = probes[i].name;
    if (report.frame != probes[i].refer_name) report.frame = probes[i].refer_name;
    report.position_m = pose_.probes[i];
  }
}

std::uint64_t Scene::pose_version() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return version_;
}

std::uint64_t Scene::Frames(std::vector<Eigen::Isometry3d>* out) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  out->assign(pose_.frames.begin(), pose_.frames.end());
  return version_;
}

void Scene::SyncActors() {
  if (ghost_) ghost_->SyncActors();
  if (contacts_) contacts_->SyncActors();
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (version_ == applied_version_) return;
    render_pose_.frames = pose_.frames;  // same sizes: no allocation
    render_pose_.probes_world = pose_.probes_world;
    applied_version_ = version_;
  }
  for (size_t k = 0; k < frame_matrices_.size(); ++k) {
    CopyToVtk(render_pose_.frames[k], frame_matrices_[k]);
  }
  for (size_t i = 0; i < probe_actors_.size(); ++i) {
    probe_actors_[i]->SetPosition(render_pose_.probes_world[i].data());
  }
}

void Scene::Render() {
  SyncActors();
  if (window_) window_->Render();
}

RgbImage Scene::Capture() {
  RequireWindow();
  Render();
  return CaptureWindow(window_);
}

void Scene::SnapshotPng(const std::filesystem::path& path) {
  RequireWindow();
  Render();
  WritePng(window_, path);
}

std::string Scene::SnapshotPngBytes() {
  RequireWindow();
  Render();
  return PngBytes(window_);
}

void Scene::Interact() {
  RequireWindow();
  vtkNew<vtkRenderWindowInteractor> interactor;
  vtkNew<vtkInteractorStyleTrackballCamera> style;
  interactor->SetInteractorStyle(style);
  interactor->SetRenderWindow(window_);
  interactor->Initialize();
  Render();
  interactor->Start();
}

}  // namespace mbstream::viewer
