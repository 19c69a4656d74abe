#include "viewer/scene/ghost_layer.h"

#include <vtkProperty.h>

#include "viewer/scene/scene_error.h"
#include "viewer/scene/visual_pipeline.h"

namespace mbstream::viewer {

namespace {

constexpr double kTint[3] = {0.55, 0.8, 1.0};  // a cool blue, blended with the part's colour

}  // namespace

GhostLayer::GhostLayer(const SceneDescription& description, vtkRenderer* renderer, double opacity)
    : solver_(description.chain, description.probes),
      opacity_(opacity),
      pose_(solver_.MakePose()),
      render_pose_(solver_.MakePose()) {
  if (!description.initial_q.empty()) solver_.Solve(description.initial_q, &pose_);
  version_ = 1;
  for (int k = 0; k < solver_.chain().frame_count(); ++k) {
    frame_matrices_.push_back(vtkSmartPointer<vtkMatrix4x4>::New());
  }
  for (const VisualPart& part : description.visuals) {
    VisualActors made;
    try {
      made = MakeVisualActors(part);
    } catch (const SceneError&) {
      if (!part.fallback) continue;
      made = MakeVisualActors(*part.fallback);
    }
    for (const vtkSmartPointer<vtkActor>& actor : made.actors) {
      if (part.frame != kWorldFrame) actor->SetUserMatrix(frame_matrices_.at(part.frame));
      double color[3];
      actor->GetProperty()->GetColor(color);
      actor->GetProperty()->SetColor(0.5 * (color[0] + kTint[0]), 0.5 * (color[1] + kTint[1]),
                                     0.5 * (color[2] + kTint[2]));
      actor->GetProperty()->SetOpacity(opacity_);
      actor->SetTexture(nullptr);  // a ghost is one tint, textured meshes too
      renderer->AddActor(actor);
      actors_.push_back(actor);
    }
  }
  SyncActors();
}

void GhostLayer::SetJointValues(std::span<const double> q_si) {
  const std::lock_guard<std::mutex> lock(mutex_);
  solver_.Solve(q_si, &pose_);
  ++version_;
}

std::vector<Eigen::Isometry3d> GhostLayer::Frames() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return pose_.frames;
}

std::uint64_t GhostLayer::pose_version() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return version_;
}

void GhostLayer::SyncActors() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (version_ == applied_version_) return;
    render_pose_.frames = pose_.frames;
    applied_version_ = version_;
  }
  for (size_t k = 0; k < frame_matrices_.size(); ++k) {
    CopyToVtk(render_pose_.frames[k], frame_matrices_[k]);
  }
}

}  // namespace mbstream::viewer
