#include "viewer/link/run_scene.h"

#include <fstream>
#include <stdexcept>

#include "shared/common/check.h"
#include "shared/model_files/model_format.h"
#include "viewer/model/model_scene.h"
#include "viewer/model/script_scene.h"
#include "viewer/script/asset_locator.h"
#include "viewer/script/diagnostics.h"
#include "viewer/script/translator.h"

namespace mbstream::viewer {

namespace {

namespace fs = std::filesystem;

// Writes the bundle's assets below `dir` (names are relative paths; anything that would
// leave `dir` is refused). Returns every directory that received a file.
std::vector<fs::path> WriteAssets(const v1::ModelBundle& bundle, const fs::path& dir) {
  std::vector<fs::path> dirs = {dir};
  for (const v1::Asset& asset : bundle.assets()) {
    const fs::path name = fs::path(asset.name()).lexically_normal();
    if (name.empty() || name.is_absolute() || *name.begin() == "..") {
      throw InputError("model asset '" + asset.name() +
                       "' is not a relative path inside the bundle; rename it");
    }
    const fs::path path = dir / name;
    fs::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << asset.data();
    if (std::find(dirs.begin(), dirs.end(), path.parent_path()) == dirs.end()) {
      dirs.push_back(path.parent_path());
    }
  }
  return dirs;
}

}  // namespace

SceneDescription SceneFromBundle(const v1::ModelInfo& model, const v1::ModelBundle& bundle,
                                 const RunSceneSource& source) {
  SceneDescription scene;
  if (source.override_scene) {
    scene = *source.override_scene;
  } else {
    const fs::path dir = source.asset_root / model.id();
    const std::vector<fs::path> dirs = WriteAssets(bundle, dir);
    if (!bundle.scene_script().empty()) {
      const scene_script::DirectoryAssetLocator assets(dirs);
      scene_script::TranslateOptions options;
      options.assets = &assets;
      options.missing_asset_advice = "submit the model with that STL file as an asset";
      const scene_script::Translation translation =
          scene_script::TranslateScript(bundle.scene_script(), options);
      if (!translation.ok()) {
        std::string message = "the scene script of model '" + model.name() + "' (" + model.id() +
                              ") does not translate:";
        for (const scene_script::Diagnostic& error : translation.errors) {
          message += "\n  " + scene_script::FormatDiagnostic(model.name() + ".scene", error);
        }
        throw InputError(message);
      }
      scene = SceneFromScript(translation.script);
    } else {
      const bool sdf =
          model_files::DetectModelFormat(bundle.urdf()) == model_files::ModelFormat::kSdf;
      scene = SceneFromModelText(bundle.urdf(), model.name() + (sdf ? ".sdf" : ".urdf"),
                                 BundleMeshFinder(dir), bundle.floating_base());
    }
  }
  return scene;
}

void CheckJointCount(const SceneDescription& scene, const v1::ModelInfo& model) {
  // The chain takes q: one value a joint, seven a free joint (a server before free bodies
  // sends no `positions`: q is then dofs long).
  const int positions = model.positions() > 0 ? model.positions() : model.dofs();
  if (scene.chain.dof() != positions) {
    throw InputError("scene '" + scene.title + "' has " + std::to_string(scene.chain.dof()) +
                     " joints but model '" + model.name() + "' (" + model.id() + ") has " +
                     std::to_string(positions) +
                     "; use a scene whose Device matches the model's joints");
  }
}

void OrderJointsAsModel(SceneDescription* scene, const v1::ModelInfo& model) {
  CheckJointCount(*scene, model);
  if (!scene->joints_named_as_model || model.joints_size() == 0) return;
  std::vector<std::string> names;
  for (const v1::JointInfo& joint : model.joints()) names.push_back(joint.name());
  try {
    scene->chain.OrderJointValuesBy(names);
  } catch (const InputError& e) {
    throw InputError("scene '" + scene->title + "' does not fit model '" + model.name() + "' (" +
                     model.id() + "): " + e.what() +
                     "; use the model's own URDF or a scene with its joints");
  }
}

SceneDescription SceneForModel(const v1::ModelInfo& model, const v1::ModelBundle& bundle,
                               const RunSceneSource& source) {
  SceneDescription scene = SceneFromBundle(model, bundle, source);
  OrderJointsAsModel(&scene, model);
  return scene;
}

}  // namespace mbstream::viewer
