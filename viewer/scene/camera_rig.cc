#include "viewer/scene/camera_rig.h"

#include <vtkCamera.h>
#include <vtkLightKit.h>
#include <vtkNew.h>

#include <algorithm>
#include <cmath>
#include <numbers>

namespace mbstream::viewer {

namespace {

constexpr double kViewAngleDeg = 30;
constexpr double kAzimuthDeg = 35;
constexpr double kElevationDeg = 20;

}  // namespace

CameraSphere CameraSphereOf(const SceneDescription& scene, const Eigen::Isometry3d& base,
                            const double bounds[6]) {
  CameraSphere sphere;
  if (scene.scene_box_m) {
    const double l = *scene.scene_box_m;
    sphere.centre = base.translation() + base.linear().col(2) * 0.4 * l;
    sphere.radius = 0.95 * l;
    return sphere;
  }
  if (bounds[0] > bounds[1]) return sphere;  // nothing visible
  const Eigen::Vector3d low(bounds[0], bounds[2], bounds[4]);
  const Eigen::Vector3d high(bounds[1], bounds[3], bounds[5]);
  sphere.centre = (low + high) / 2;
  sphere.radius = std::max(0.65 * (high - low).norm(), 0.05);
  return sphere;
}

namespace {

// From the target towards the eye.
Eigen::Vector3d ViewDirection(const Eigen::Isometry3d& base) {
  const double d2r = std::numbers::pi / 180;
  const Eigen::Vector3d x = base.linear().col(0);
  const Eigen::Vector3d y = base.linear().col(1);
  const Eigen::Vector3d up = base.linear().col(2);
  return std::cos(kElevationDeg * d2r) *
             (std::cos(kAzimuthDeg * d2r) * x + std::sin(kAzimuthDeg * d2r) * y) +
         std::sin(kElevationDeg * d2r) * up;
}

void SetCamera(vtkRenderer* renderer, const Eigen::Vector3d& centre, const Eigen::Vector3d& eye,
               const Eigen::Vector3d& up, double near, double far) {
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetViewAngle(kViewAngleDeg);
  camera->SetFocalPoint(centre.data());
  camera->SetPosition(eye.data());
  camera->SetViewUp(up.data());
  camera->OrthogonalizeViewUp();
  camera->SetClippingRange(near, far);
}

}  // namespace

void FrameBox(vtkRenderer* renderer, const double bounds[6], const Eigen::Isometry3d& base,
              double aspect) {
  if (bounds[0] > bounds[1]) {  // nothing visible
    PlaceCamera(renderer, CameraSphere{}, base);
    return;
  }
  const Eigen::Vector3d low(bounds[0], bounds[2], bounds[4]);
  const Eigen::Vector3d high(bounds[1], bounds[3], bounds[5]);
  const Eigen::Vector3d centre = (low + high) / 2;
  const Eigen::Vector3d back = ViewDirection(base);  // towards the eye
  const Eigen::Vector3d right = base.linear().col(2).cross(back).normalized();
  const Eigen::Vector3d up = back.cross(right);
  const double tan_v = std::tan(kViewAngleDeg / 2 * std::numbers::pi / 180) * kFill;
  const double tan_h = tan_v * std::max(aspect, 0.1);
  // Each corner at depth (distance - toward) must satisfy |side| <= tan * depth.
  double distance = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Eigen::Vector3d p(corner & 1 ? high.x() : low.x(), corner & 2 ? high.y() : low.y(),
                            corner & 4 ? high.z() : low.z());
    const Eigen::Vector3d d = p - centre;
    const double toward = d.dot(back);
    distance = std::max(
        {distance, toward + std::abs(d.dot(right)) / tan_h, toward + std::abs(d.dot(up)) / tan_v});
  }
  const double radius = std::max((high - low).norm() / 2, 0.05);
  distance = std::max(distance, 0.1);
  SetCamera(renderer, centre, centre + distance * back, base.linear().col(2),
            std::max(distance - 2 * radius, 0.01 * distance), distance + 2 * radius);
}

void PlaceCamera(vtkRenderer* renderer, const CameraSphere& sphere, const Eigen::Isometry3d& base) {
  const double d2r = std::numbers::pi / 180;
  const Eigen::Vector3d up = base.linear().col(2);
  const Eigen::Vector3d direction = ViewDirection(base);
  const double distance = sphere.radius / std::sin(kViewAngleDeg / 2 * d2r);
  SetCamera(renderer, sphere.centre, sphere.centre + distance * direction, up,
            std::max(distance - 2 * sphere.radius, 0.01 * distance), distance + 2 * sphere.radius);
}

void AddLights(vtkRenderer* renderer) {
  vtkNew<vtkLightKit> kit;
  kit->SetKeyLightIntensity(0.85);
  kit->AddLightsToRenderer(renderer);
}

}  // namespace mbstream::viewer
