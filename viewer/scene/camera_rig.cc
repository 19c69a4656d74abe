#include "viewer/scene/camera_rig.h"

#include <vtkCamera.h>
#include <vtkLightKit.h>
#include <vtkNew.h>

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

void PlaceCamera(vtkRenderer* renderer, const CameraSphere& sphere, const Eigen::Isometry3d& base) {
  const double d2r = std::numbers::pi / 180;
  const Eigen::Vector3d x = base.linear().col(0);
  const Eigen::Vector3d y = base.linear().col(1);
  const Eigen::Vector3d up = base.linear().col(2);
  const Eigen::Vector3d direction =
      std::cos(kElevationDeg * d2r) *
          (std::cos(kAzimuthDeg * d2r) * x + std::sin(kAzimuthDeg * d2r) * y) +
      std::sin(kElevationDeg * d2r) * up;
  const double distance = sphere.radius / std::sin(kViewAngleDeg / 2 * d2r);
  const Eigen::Vector3d eye = sphere.centre + distance * direction;
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetViewAngle(kViewAngleDeg);
  camera->SetFocalPoint(sphere.centre.data());
  camera->SetPosition(eye.data());
  camera->SetViewUp(up.data());
  camera->OrthogonalizeViewUp();
  camera->SetClippingRange(std::max(distance - 2 * sphere.radius, 0.01 * distance),
                           distance + 2 * sphere.radius);
}

void AddLights(vtkRenderer* renderer) {
  vtkNew<vtkLightKit> kit;
  kit->SetKeyLightIntensity(0.85);
  kit->AddLightsToRenderer(renderer);
}

}  // namespace mbstream::viewer
