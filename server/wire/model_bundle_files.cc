#include "server/wire/model_bundle_files.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "server/common/check.h"

namespace mbstream {

namespace {

namespace fs = std::filesystem;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("cannot read " + path.string() + ": check the path and permissions");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::string Lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

// Files directly in `dir` with extension `ext` (lower case, with the dot), sorted.
std::vector<fs::path> FilesWithExtension(const fs::path& dir, const std::string& ext) {
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
    if (entry.is_regular_file() && Lower(entry.path().extension().string()) == ext) {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

void AddAsset(const std::string& name, const fs::path& path, v1::ModelBundle* bundle) {
  for (const v1::Asset& asset : bundle->assets()) {
    if (asset.name() == name) {
      throw InputError("asset '" + name + "' (" + path.string() +
                       ") is given twice; rename one of the files");
    }
  }
  v1::Asset* asset = bundle->add_assets();
  asset->set_name(name);
  asset->set_data(ReadFile(path));
}

}  // namespace

v1::ModelBundle ReadModelBundle(const std::string& model_path, const std::string& scene_path,
                                const std::vector<std::string>& asset_paths,
                                const std::string& name) {
  v1::ModelBundle bundle;
  bundle.set_name(name);
  fs::path urdf_path = model_path;
  std::error_code error;
  if (fs::is_directory(model_path, error)) {
    const fs::path dir = model_path;
    const std::vector<fs::path> urdfs = FilesWithExtension(dir, ".urdf");
    if (urdfs.size() != 1) {
      throw InputError(model_path + ": a model directory needs exactly one .urdf file, found " +
                       std::to_string(urdfs.size()) + "; name the URDF file instead");
    }
    urdf_path = urdfs[0];
    const std::vector<fs::path> scenes = FilesWithExtension(dir, ".scene");
    if (scenes.size() == 1 && scene_path.empty()) bundle.set_scene_script(ReadFile(scenes[0]));
    for (const fs::directory_entry& entry : fs::recursive_directory_iterator(dir)) {
      if (entry.is_regular_file() && Lower(entry.path().extension().string()) == ".stl") {
        AddAsset(fs::relative(entry.path(), dir).generic_string(), entry.path(), &bundle);
      }
    }
  }
  bundle.set_urdf(ReadFile(urdf_path));
  bundle.set_urdf_file_name(urdf_path.string());
  if (!scene_path.empty()) bundle.set_scene_script(ReadFile(scene_path));
  for (const std::string& path : asset_paths) {
    AddAsset(fs::path(path).filename().string(), path, &bundle);
  }
  return bundle;
}

}  // namespace mbstream
