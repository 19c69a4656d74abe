// Loading a scene description for the command line: a scene script (translated, errors
// printed as FILE:LINE:COL: message) or a model file's visuals (URDF or SDFormat).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "viewer/model/scene_description.h"
#include "viewer/script/translator.h"

namespace mbstream::viewer {

// Translates `file`, looking for STL parts in `asset_dirs` and then the script's own
// directory. Prints every error to stderr.
scene_script::Translation TranslateForCommandLine(const std::string& file,
                                                  const std::vector<std::string>& asset_dirs);

// The scene of a script or model file (URDF or SDFormat, by content; its meshes found as
// `mbstream submit` finds them, with `package_path`), or nullopt after printing what is wrong.
std::optional<SceneDescription> LoadScene(const std::string& scene_file,
                                          const std::string& model_file,
                                          const std::vector<std::string>& asset_dirs,
                                          const std::vector<std::string>& package_path = {},
                                          bool floating_base = false);

// "0,30,-45.5" -> values; nullopt after printing what is wrong.
std::optional<std::vector<double>> ParsePose(const std::string& text);

}  // namespace mbstream::viewer
