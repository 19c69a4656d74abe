#include "server/parse/mesh_source.h"

#include <fstream>
#include <sstream>
#include <utility>

#include "shared/model_files/mesh_file_search.h"
#include "shared/model_files/mesh_lookup.h"

namespace mbstream {

MeshSource DiskMeshSource(const std::filesystem::path& directory,
                          const std::vector<std::string>& package_path) {
  const model_files::MeshFileSearch search(directory.empty() ? "." : directory,
                                           model_files::PackagePath(package_path));
  return [search](const std::string& filename) -> std::optional<std::string> {
    const std::filesystem::path found = search.Find(filename).found;
    if (found.empty()) return std::nullopt;
    std::ifstream in(found, std::ios::binary);
    if (!in) return std::nullopt;
    std::ostringstream bytes;
    bytes << in.rdbuf();
    return bytes.str();
  };
}

MeshSource AssetMeshSource(std::function<const std::string*(const std::string& name)> asset) {
  return [asset = std::move(asset)](const std::string& filename) -> std::optional<std::string> {
    for (const std::string& key : model_files::MeshAssetKeys(filename)) {
      if (const std::string* bytes = asset(key)) return *bytes;
    }
    return std::nullopt;
  };
}

}  // namespace mbstream
