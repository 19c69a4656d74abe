#include "viewer/app/scene_loading.h"

#include <spdlog/spdlog.h>

#include <filesystem>
#include <iostream>

#include "viewer/model/model_scene.h"
#include "viewer/model/script_scene.h"
#include "viewer/script/lexer.h"

namespace mbstream::viewer {

namespace ss = scene_script;

ss::Translation TranslateForCommandLine(const std::string& file,
                                        const std::vector<std::string>& asset_dirs) {
  std::vector<std::filesystem::path> dirs(asset_dirs.begin(), asset_dirs.end());
  dirs.push_back(std::filesystem::path(file).parent_path().empty()
                     ? std::filesystem::path(".")
                     : std::filesystem::path(file).parent_path());
  const ss::DirectoryAssetLocator assets(dirs);
  ss::TranslateOptions options;
  options.assets = &assets;
  options.missing_asset_advice = "pass --asset-dir DIR with the directory that holds it";
  ss::Translation translation = ss::TranslateScriptFile(file, options);
  for (const ss::Diagnostic& error : translation.errors) {
    std::cerr << ss::FormatDiagnostic(file, error) << "\n";
  }
  return translation;
}

std::optional<SceneDescription> LoadScene(const std::string& scene_file,
                                          const std::string& model_file,
                                          const std::vector<std::string>& asset_dirs,
                                          const std::vector<std::string>& package_path,
                                          bool floating_base) {
  if (!scene_file.empty()) {
    const ss::Translation translation = TranslateForCommandLine(scene_file, asset_dirs);
    if (!translation.ok()) {
      spdlog::error("{}: {} error(s); the scene is built only from a script without errors",
                    scene_file, translation.errors.size());
      return std::nullopt;
    }
    return SceneFromScript(translation.script);
  }
  try {
    SceneDescription scene = SceneFromModelFile(model_file, package_path, floating_base);
    for (const std::string& warning : scene.warnings) spdlog::warn("{}", warning);
    return scene;
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return std::nullopt;
  }
}

std::optional<std::vector<double>> ParsePose(const std::string& text) {
  std::vector<double> values;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = std::min(text.find(',', start), text.size());
    std::string item = text.substr(start, comma - start);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    double value = 0;
    if (!ss::ParseNumber(item, &value)) {
      std::cerr << "--pose: '" << item << "' (value " << values.size() + 1
                << ") is not a number; give comma-separated joint values in degrees or mm, "
                   "e.g. --pose 0,30,-45,0,60,0\n";
      return std::nullopt;
    }
    values.push_back(value);
    start = comma + 1;
  }
  return values;
}

}  // namespace mbstream::viewer
