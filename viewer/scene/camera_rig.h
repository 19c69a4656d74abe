// The fixed camera and the lights of a scene.
//
// The camera looks at a sphere that holds the mechanism in every pose: with the script's
// LBox L, centred 0.4 L above the device base along the base's z axis, radius 0.95 L (the
// IRB 1600 stretched straight up still fits);
// without it, around the bounds of the first pose. It looks from the base's +x side (the
// seed's "towards the viewer"), turned 35 degrees about the base's z axis and raised 20
// degrees, with the base's z axis up on screen. It is not moved when the robot moves.
// Without LBox the camera comes as close as lets the bounding box of the first pose fill
// kFill of the picture's height or width (whichever binds first): a model as published
// is framed at its initial pose.
#pragma once

#include <vtkRenderer.h>

#include "viewer/model/scene_description.h"

namespace mbstream::viewer {

struct CameraSphere {
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  double radius = 1;
};

// `bounds` (xmin, xmax, ymin, ymax, zmin, zmax) of the first pose, used without LBox.
CameraSphere CameraSphereOf(const SceneDescription& scene, const Eigen::Isometry3d& base,
                            const double bounds[6]);

void PlaceCamera(vtkRenderer* renderer, const CameraSphere& sphere, const Eigen::Isometry3d& base);

inline constexpr double kFill = 0.9;

// Without LBox: the camera in the same direction as PlaceCamera, at the distance at which
// the box `bounds` fills kFill of a picture of `aspect` (width / height).
void FrameBox(vtkRenderer* renderer, const double bounds[6], const Eigen::Isometry3d& base,
              double aspect);

void AddLights(vtkRenderer* renderer);

}  // namespace mbstream::viewer
