#include "shared/model_files/sdf_includes.h"

#include <algorithm>
#include <string_view>
#include <system_error>

#include "shared/model_files/mesh_file_search.h"

namespace mbstream::model_files {

namespace {

namespace fs = std::filesystem;

constexpr std::string_view kModel = "model://";
constexpr std::string_view kFile = "file://";

bool Exists(const fs::path& path) {
  std::error_code error;
  return fs::exists(path, error);
}

}  // namespace

SdfIncludeSearch FindSdfInclude(const std::string& uri, const SdfIncludePath& path) {
  SdfIncludeSearch search;
  const auto attempt = [&](const fs::path& candidate) {
    const fs::path normal = candidate.lexically_normal();
    if (std::find(search.tried.begin(), search.tried.end(), normal) != search.tried.end()) {
      return false;
    }
    search.tried.push_back(normal);
    if (!Exists(normal)) return false;
    search.found = normal;
    return true;
  };
  if (uri.starts_with(kFile)) {
    attempt(uri.substr(kFile.size()));
    return search;
  }
  if (!uri.starts_with(kModel)) {
    const fs::path bare(uri);
    attempt(bare.is_absolute() ? bare : path.file_dir / bare);
    return search;
  }
  const std::string rest_of_uri = uri.substr(kModel.size());
  const size_t slash = rest_of_uri.find('/');
  const std::string name = rest_of_uri.substr(0, slash);
  const std::string rest = slash == std::string::npos ? "" : rest_of_uri.substr(slash + 1);
  std::vector<fs::path> folders = PackageFolders(path.package_path, name);
  for (fs::path dir = fs::absolute(path.file_dir).lexically_normal();; dir = dir.parent_path()) {
    folders.push_back(dir / name);
    if (dir == dir.parent_path()) break;
  }
  for (const fs::path& folder : folders) {
    if (!rest.empty()) {
      if (attempt(folder / rest)) return search;
      continue;
    }
    // libsdformat reads a model folder's model.config; a folder with only a model.sdf is
    // given as that file.
    if (attempt(folder / "model.config")) {
      search.found = folder;
      return search;
    }
    if (attempt(folder / "model.sdf")) return search;
  }
  return search;
}

}  // namespace mbstream::model_files
