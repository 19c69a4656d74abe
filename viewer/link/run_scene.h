// The scene of a run from what the server sends (the model's scene script and assets, or
// its URDF's visuals), or from a scene file given on the command line.
#pragma once

#include <filesystem>
#include <optional>
#include <string>

#include "mbstream/v1/model.pb.h"
#include "viewer/model/scene_description.h"

namespace mbstream::viewer {

struct RunSceneSource {
  std::optional<SceneDescription> override_scene;  // --scene FILE, already loaded
  std::filesystem::path asset_root;  // where the bundles' assets are written (per model id)
};

// The scene for a model: the override, else the bundle's scene script (translated; every
// error as "model NAME scene LINE:COL: message"), else its URDF's visuals; its joints
// ordered as the model's (OrderJointsAsModel). Throws InputError with the message.
SceneDescription SceneForModel(const v1::ModelInfo& model, const v1::ModelBundle& bundle,
                               const RunSceneSource& source);

// The same without the joint-count check (a scene loaded by hand, no run to match).
SceneDescription SceneFromBundle(const v1::ModelInfo& model, const v1::ModelBundle& bundle,
                                 const RunSceneSource& source);

// Throws InputError naming both counts when the scene does not fit the model.
void CheckJointCount(const SceneDescription& scene, const v1::ModelInfo& model);

// CheckJointCount; then, for a scene whose joints carry the model's names (a URDF scene),
// orders its joint values by the names the server sends (ModelInfo.joints, the order of q
// on the wire). Throws InputError naming the joints that differ when the names do
// not match. A scene script's Device names its own joints: only the count is checked.
void OrderJointsAsModel(SceneDescription* scene, const v1::ModelInfo& model);

}  // namespace mbstream::viewer
