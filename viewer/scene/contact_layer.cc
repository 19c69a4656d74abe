#include "viewer/scene/contact_layer.h"

#include <algorithm>

#include <vtkArrowSource.h>
#include <vtkGlyph3D.h>
#include <vtkPointData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkSphereSource.h>

namespace mbstream::viewer {

namespace {

constexpr double kPointRadius = 0.008;                // m, the contact point's sphere
constexpr double kPointColor[3] = {1.0, 0.85, 0.1};   // yellow
constexpr double kArrowColor[3] = {0.95, 0.25, 0.2};  // red

// A glyph pipeline on `input` with `source`, drawn in `color`.
vtkSmartPointer<vtkActor> GlyphActor(vtkPolyData* input, vtkAlgorithmOutput* source, bool oriented,
                                     const double (&color)[3]) {
  auto glyph = vtkSmartPointer<vtkGlyph3D>::New();
  glyph->SetInputData(input);
  glyph->SetSourceConnection(source);
  if (oriented) {  // along the vector, as long as it is (the arrow source is 1 m long)
    glyph->SetVectorModeToUseVector();
    glyph->SetScaleModeToScaleByVector();
    glyph->OrientOn();
    glyph->SetScaleFactor(1.0);
  } else {
    glyph->SetScaleModeToDataScalingOff();
    glyph->OrientOff();
  }
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputConnection(glyph->GetOutputPort());
  mapper->ScalarVisibilityOff();
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(color[0], color[1], color[2]);
  actor->PickableOff();
  return actor;
}

}  // namespace

ContactLayer::ContactLayer(vtkRenderer* renderer, double scale)
    : scale_(scale), marks_(kMaxContacts), render_marks_(kMaxContacts) {
  points_ = vtkSmartPointer<vtkPoints>::New();
  points_->SetDataTypeToDouble();
  vectors_ = vtkSmartPointer<vtkDoubleArray>::New();
  vectors_->SetNumberOfComponents(3);
  vectors_->SetName("contact_force_arrow_m");
  input_ = vtkSmartPointer<vtkPolyData>::New();
  input_->SetPoints(points_);
  input_->GetPointData()->SetVectors(vectors_);
  auto sphere = vtkSmartPointer<vtkSphereSource>::New();
  sphere->SetRadius(kPointRadius);
  sphere->SetThetaResolution(12);
  sphere->SetPhiResolution(8);
  auto arrow = vtkSmartPointer<vtkArrowSource>::New();
  arrow->SetShaftRadius(0.02);
  arrow->SetTipRadius(0.06);
  arrow->SetTipLength(0.2);
  points_actor_ = GlyphActor(input_, sphere->GetOutputPort(), false, kPointColor);
  arrows_actor_ = GlyphActor(input_, arrow->GetOutputPort(), true, kArrowColor);
  renderer->AddActor(points_actor_);
  renderer->AddActor(arrows_actor_);
  points_actor_->VisibilityOff();  // until a frame has contacts
  arrows_actor_->VisibilityOff();
}

void ContactLayer::SetContacts(std::span<const ContactMark> contacts) {
  const std::lock_guard<std::mutex> lock(mutex_);
  count_ = static_cast<int>(std::min<size_t>(contacts.size(), kMaxContacts));
  std::copy_n(contacts.begin(), count_, marks_.begin());
  if (count_ > 0) ++frames_with_;
  ++version_;
}

int ContactLayer::count() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return count_;
}

std::int64_t ContactLayer::frames_with_contacts() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return frames_with_;
}

void ContactLayer::Marks(std::vector<ContactMark>* out) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  out->assign(marks_.begin(), marks_.begin() + count_);
}

void ContactLayer::SyncActors() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (version_ == applied_version_) return;
    render_count_ = count_;
    std::copy_n(marks_.begin(), count_, render_marks_.begin());
    applied_version_ = version_;
  }
  for (int i = 0; i < render_count_; ++i) {
    force_max_ = std::max(force_max_, render_marks_[i].force.norm());
  }
  const double scale = scale_ > 0.0 ? scale_ : (force_max_ > 0.0 ? kAutoLength / force_max_ : 0.0);
  points_->SetNumberOfPoints(render_count_);
  vectors_->SetNumberOfTuples(render_count_);
  for (int i = 0; i < render_count_; ++i) {
    const ContactMark& m = render_marks_[i];
    points_->SetPoint(i, m.point.x(), m.point.y(), m.point.z());
    const Eigen::Vector3d arrow = scale * m.force;
    vectors_->SetTuple3(i, arrow.x(), arrow.y(), arrow.z());
  }
  points_->Modified();
  vectors_->Modified();
  input_->Modified();
  points_actor_->SetVisibility(render_count_ > 0);
  arrows_actor_->SetVisibility(render_count_ > 0);
}

std::vector<Eigen::Vector3d> ContactLayer::ArrowTips() const {
  std::vector<Eigen::Vector3d> tips;
  for (vtkIdType i = 0; i < points_->GetNumberOfPoints(); ++i) {
    double p[3], v[3];
    points_->GetPoint(i, p);
    vectors_->GetTuple(i, v);
    tips.emplace_back(p[0] + v[0], p[1] + v[1], p[2] + v[2]);
  }
  return tips;
}

}  // namespace mbstream::viewer
