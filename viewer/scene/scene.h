// The VTK scene of one mechanism.
//
// Two sides, so that a network thread never waits for a render:
//  - pose side (any thread, no VTK, no allocation per call): SetJointValues computes every
//    link frame and every probe at once; ProbeReports returns the probes of the newest pose.
//  - render side (the thread that created the Scene): Render applies the newest pose to
//    the actors' user matrices (no pipeline is rebuilt) and draws; Capture/Snapshot read
//    the pixels back.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include <vtkActor.h>
#include <vtkMatrix4x4.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>

#include "viewer/kinematics/pose_solver.h"
#include "viewer/model/scene_description.h"
#include "viewer/scene/contact_layer.h"
#include "viewer/scene/ghost_layer.h"
#include "viewer/scene/mesh_file_reader.h"
#include "viewer/scene/probe_report.h"
#include "viewer/scene/rgb_image.h"

namespace mbstream::viewer {

struct SceneOptions {
  int width = 960;
  int height = 720;
  bool offscreen = false;  // needs an X display all the same (Xvfb: xvfb-run -a)
  std::string window_title = "mbstream viewer";
  // When the model's mesh files hold more triangles than this, each is decimated on load
  // in proportion (quadric clustering, which keeps the silhouette within a grid cell) so
  // that the model draws about this many; 0 = never decimate. See docs/performance.md.
  long long triangle_budget = kDefaultTriangleBudget;
  static constexpr long long kDefaultTriangleBudget = 100'000;
  // > 0: the scene also draws a ghost (a second, translucent copy of the mechanism posed on
  // its own, ghost_layer.h) with this opacity.
  double ghost_opacity = 0.0;
  // The scene also draws each frame's contact points and force arrows (contact_layer.h);
  // contact_scale in m/N, 0 = automatic.
  bool contacts = false;
  double contact_scale = 0.0;
};

// A render window with the options' size, offscreen flag and title (no X request yet: the
// window opens its X connection, unless given one, and appears at its first render).
vtkSmartPointer<vtkRenderWindow> MakeRenderWindow(const SceneOptions& options);

// The one HUD line that names the meshes drawn as placeholder boxes: "3 meshes missing:
// a.dae, b.dae, c.dae", at most `shown` names then "and N more"; each name is the file's own
// name (no folders), once, "(unreadable)" after a file that is there but cannot be read.
// Empty when nothing is missing.
struct MissingMesh {
  std::string filename;  // as the model wrote it
  bool unreadable = false;
};
std::string MissingMeshesLine(const std::vector<MissingMesh>& missing, int shown = 4);

class Scene {
 public:
  // Builds every pipeline, the camera and the lights; poses the initial joint values.
  // A mesh file that cannot be read is drawn as the part's fallback (a URDF link's
  // placeholder box) with a logged warning, and named on one HUD line (missing_meshes_line)
  // with the placeholders of missing files; without one, throws SceneError. Textures are
  // drawn where the mesh file's image is beside it (those that cannot be are logged once per
  // scene). Throws InputError (shared/common/check.h) on a bad description.
  // The scene makes its own window (which opens an X connection at its first render).
  Scene(SceneDescription description, SceneOptions options);
  // The same, drawn into `window` (a ViewWindow's, which outlives the Scene; its size,
  // offscreen flag and title are the window's own) by a renderer of the scene's, added here
  // and removed by the destructor. `window` null: no window (the display is lost): the pose
  // side works, Render does nothing, Capture and the snapshots throw SceneError.
  Scene(SceneDescription description, SceneOptions options, vtkRenderWindow* window);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  const SceneDescription& description() const { return description_; }
  int dof() const { return solver_.dof(); }

  // ---- pose side: thread-safe, no VTK calls.
  // Joint values in SI (rad, m), in the chain's joint order. Throws InputError
  // naming both counts when q_si.size() != dof().
  void SetJointValues(std::span<const double> q_si);
  std::vector<ProbeReport> ProbeReports() const;
  // The same into `out`, reusing its storage.
  void ProbeReports(std::vector<ProbeReport>* out) const;
  // Increases with every SetJointValues.
  std::uint64_t pose_version() const;
  // Every frame of the newest pose, in World, into `out` (reusing its storage); returns the
  // pose's version.
  std::uint64_t Frames(std::vector<Eigen::Isometry3d>* out) const;

  // ---- render side: the thread that created the Scene.
  // Copies the newest pose into the actors' user matrices and the probe markers (no
  // pipeline is touched); does nothing when the pose has not changed.
  void SyncActors();
  // SyncActors, then draws.
  void Render();
  RgbImage Capture();  // renders, then reads the frame
  // Renders and writes a PNG file; throws SceneError when the file cannot be written.
  void SnapshotPng(const std::filesystem::path& path);
  std::string SnapshotPngBytes();  // renders, returns PNG bytes
  // Window mode: mouse interaction (trackball camera) until the window is closed.
  void Interact();
  // The display went away: the scene stops drawing and lets go of its window without a word
  // to it. Its renderer and actors are kept for good, since freeing their graphics resources
  // would talk to the lost X server (one scene at most: later ones are built without a
  // window).
  void ForgetWindow();

  // Null when the scene has no window (see the constructor).
  vtkRenderWindow* render_window() { return window_; }
  vtkRenderer* renderer() { return renderer_; }
  // The actors that show parts (probe markers and the ghost excluded), in the order built,
  // and the frame each one follows (kWorldFrame: fixed in World). Their mappers' inputs are
  // in that frame's axes; the actors' own transforms are the identity.
  const std::vector<vtkSmartPointer<vtkActor>>& part_actors() const { return part_actors_; }
  const std::vector<int>& part_frames() const { return part_frames_; }
  // Number of actors that show parts (probe markers excluded).
  int part_actor_count() const { return static_cast<int>(part_actors_.size()); }
  // Triangles drawn by the part actors.
  long long triangle_count() const { return triangle_count_; }
  // The meshes drawn as placeholder boxes (missing, or unreadable), in the order of the
  // visuals, and the one HUD line that names them (MissingMeshesLine; empty: none, and no
  // text actor).
  const std::vector<MissingMesh>& missing_meshes() const { return missing_meshes_; }
  std::string missing_meshes_line() const { return MissingMeshesLine(missing_meshes_); }
  // The ghost (SceneOptions::ghost_opacity > 0), or nullptr. Its pose side is thread-safe.
  GhostLayer* ghost() { return ghost_.get(); }
  // The contacts' layer (SceneOptions::contacts), or nullptr. Its pose side is thread-safe.
  ContactLayer* contacts() { return contacts_.get(); }

 private:
  SceneDescription description_;
  PoseSolver solver_;

  mutable std::mutex mutex_;  // guards pose_ and version_
  Pose pose_;
  std::uint64_t version_ = 0;

  // Render side only.
  Pose render_pose_;
  std::uint64_t applied_version_ = ~std::uint64_t{0};
  vtkSmartPointer<vtkRenderWindow> window_;
  bool owns_window_ = false;  // made here (else a ViewWindow's, or none)
  vtkSmartPointer<vtkRenderer> renderer_;
  std::vector<vtkSmartPointer<vtkMatrix4x4>> frame_matrices_;  // one per frame
  std::vector<vtkSmartPointer<vtkActor>> part_actors_;
  std::vector<int> part_frames_;  // per part actor
  std::vector<vtkSmartPointer<vtkActor>> probe_actors_;
  std::vector<MissingMesh> missing_meshes_;
  vtkSmartPointer<vtkTextActor> missing_meshes_actor_;  // top left; null when none is missing
  long long triangle_count_ = 0;
  std::unique_ptr<GhostLayer> ghost_;
  std::unique_ptr<ContactLayer> contacts_;

  Scene(SceneDescription description, const SceneOptions& options,
        vtkSmartPointer<vtkRenderWindow> window, bool owns_window);
  void AddPart(const VisualPart& part, long long max_triangles, bool* textured);
  void AddMissingMeshesLine();
  // Throws SceneError when there is no window to read pixels from.
  void RequireWindow() const;
  // Per visual: the triangles its mesh file may keep (0 = all), from the budget.
  std::vector<long long> TriangleShares(long long budget) const;
};

}  // namespace mbstream::viewer
