// A scene from a translated scene script (lengths mm and degrees -> metres and radians).
#pragma once

#include "viewer/model/scene_description.h"
#include "viewer/script/script.h"

namespace mbstream::viewer {

// The Device's chain: base = the Device transform in World, joint k = its pre-transform,
// motion about axis x|y|z and post-transform, hanging from frame `parent`.
KinematicChain ChainFromDevice(const scene_script::DeviceCommand& device);

// Needs a script that translated without errors. Visuals: every part of every device-link
// Set moves with its frame; a rendered part or assembly that is neither a link nor a
// component of another Set stands still in World. Colours: the nearest Render on the way
// from a part up to its link (the part's own first), else light grey.
SceneDescription SceneFromScript(const scene_script::Script& script);

}  // namespace mbstream::viewer
