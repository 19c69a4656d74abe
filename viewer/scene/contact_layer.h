// A run's active contacts drawn in the scene (mbstream-viewer --contacts): a small sphere at
// each contact point and an arrow along the contact force on the first body of the pair
// (normal plus friction), in World. The server sends them with each frame when asked
// (SubscribeRequest.Start.contacts, frame.proto's FrameContact).
//
// Arrow length: `scale` metres per newton, or, with scale 0, 0.25 m for the largest force
// drawn so far (the arrows of one run stay comparable with each other).
//
// Like Scene, two sides: SetContacts (any thread, no VTK, no allocation up to kMaxContacts)
// and SyncActors (the render thread that built it).
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <mutex>
#include <span>
#include <vector>

#include <vtkActor.h>
#include <vtkDoubleArray.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>

namespace mbstream::viewer {

// One contact as the layer draws it, in World (m, N).
struct ContactMark {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // m
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // N, on the pair's first body
};

class ContactLayer {
 public:
  // More contacts in one frame than this are drawn as the first kMaxContacts.
  static constexpr int kMaxContacts = 1024;
  static constexpr double kAutoLength = 0.25;  // m, the largest force's arrow with scale 0

  // Builds the layer's two actors into `renderer`; `scale` in m/N (0: automatic, above).
  ContactLayer(vtkRenderer* renderer, double scale);

  // ---- pose side: thread-safe. The frame's contacts (at most kMaxContacts are kept).
  void SetContacts(std::span<const ContactMark> contacts);
  // Contacts in the newest frame, and how many frames had at least one.
  int count() const;
  std::int64_t frames_with_contacts() const;
  // The newest frame's contacts into `out` (its storage reused); and the layer's scale.
  void Marks(std::vector<ContactMark>* out) const;
  double scale() const { return scale_; }

  // ---- render side.
  void SyncActors();
  // After SyncActors: the arrows' tips as drawn (point + length * force direction), in World.
  std::vector<Eigen::Vector3d> ArrowTips() const;
  vtkActor* points_actor() { return points_actor_; }
  vtkActor* arrows_actor() { return arrows_actor_; }

 private:
  const double scale_;
  mutable std::mutex mutex_;        // guards marks_, count_, version_, frames_with_
  std::vector<ContactMark> marks_;  // kMaxContacts, the first count_ in use
  int count_ = 0;
  std::uint64_t version_ = 0;
  std::int64_t frames_with_ = 0;
  // Render side only.
  std::vector<ContactMark> render_marks_;
  int render_count_ = 0;
  std::uint64_t applied_version_ = 0;
  double force_max_ = 0.0;  // N, the largest force drawn so far (automatic scale)
  vtkSmartPointer<vtkPoints> points_;
  vtkSmartPointer<vtkDoubleArray> vectors_;  // per point: the arrow, m, in World
  vtkSmartPointer<vtkPolyData> input_;
  vtkSmartPointer<vtkActor> points_actor_, arrows_actor_;
};

}  // namespace mbstream::viewer
