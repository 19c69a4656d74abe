#include "shared/model_files/mesh_lookup.h"

#include <algorithm>
#include <string_view>
#include <system_error>

namespace mbstream::model_files {

namespace {

constexpr std::string_view kPackage = "package://";
constexpr std::string_view kFile = "file://";
constexpr std::string_view kModel = "model://";  // SDFormat's (Gazebo's) package://

bool StartsWith(const std::string& s, std::string_view prefix) {
  return s.compare(0, prefix.size(), prefix) == 0;
}

std::string BaseName(const std::string& filename) {
  const size_t slash = filename.find_last_of('/');
  return slash == std::string::npos ? filename : filename.substr(slash + 1);
}

// REST of package://PKG/REST, or "".
std::string PackageRest(const std::string& filename) {
  const size_t scheme = StartsWith(filename, kPackage) ? kPackage.size()
                        : StartsWith(filename, kModel) ? kModel.size()
                                                       : 0;
  if (scheme == 0) return "";
  const std::string path = filename.substr(scheme);
  const size_t slash = path.find('/');
  return slash == std::string::npos ? "" : path.substr(slash + 1);
}

void AddOnce(std::vector<std::string>* keys, const std::string& key) {
  if (!key.empty() && std::find(keys->begin(), keys->end(), key) == keys->end()) {
    keys->push_back(key);
  }
}

}  // namespace

std::string WithoutScheme(const std::string& filename) {
  if (StartsWith(filename, kPackage)) return filename.substr(kPackage.size());
  if (StartsWith(filename, kFile)) return filename.substr(kFile.size());
  if (StartsWith(filename, kModel)) return filename.substr(kModel.size());
  return filename;
}

std::string BundleAssetName(const std::string& filename) {
  const std::filesystem::path normal =
      std::filesystem::path(WithoutScheme(filename)).lexically_normal();
  std::filesystem::path relative;
  bool leading = true;
  for (const std::filesystem::path& step : normal.relative_path()) {
    if (leading && (step == ".." || step == ".")) continue;
    leading = false;
    relative /= step;
  }
  return relative.generic_string();
}

std::vector<std::string> MeshAssetKeys(const std::string& filename) {
  std::vector<std::string> keys;
  AddOnce(&keys, filename);
  AddOnce(&keys, WithoutScheme(filename));
  AddOnce(&keys, BundleAssetName(filename));
  AddOnce(&keys, PackageRest(filename));
  AddOnce(&keys, BaseName(filename));
  return keys;
}

std::vector<std::filesystem::path> MeshFileCandidates(const std::string& filename,
                                                      const std::filesystem::path& directory) {
  std::vector<std::filesystem::path> candidates;
  const std::filesystem::path bare(WithoutScheme(filename));
  if (bare.is_absolute()) candidates.push_back(bare);
  for (const std::string& key : MeshAssetKeys(filename)) {
    if (key == filename && filename != WithoutScheme(filename)) continue;  // has a scheme
    const std::filesystem::path relative(key);
    if (!relative.is_absolute()) candidates.push_back(directory / relative);
  }
  if (const std::string rest = PackageRest(filename); !rest.empty()) {
    candidates.push_back(directory.parent_path() / rest);
  }
  return candidates;
}

std::filesystem::path FindMeshFile(const std::string& filename,
                                   const std::filesystem::path& directory) {
  for (const std::filesystem::path& candidate : MeshFileCandidates(filename, directory)) {
    std::error_code error;
    if (std::filesystem::is_regular_file(candidate, error)) return candidate;
  }
  return {};
}

}  // namespace mbstream::model_files
