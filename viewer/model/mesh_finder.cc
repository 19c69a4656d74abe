#include "viewer/model/mesh_finder.h"

#include "shared/model_files/mesh_file_search.h"
#include "shared/model_files/mesh_lookup.h"

namespace mbstream::viewer {

MeshFinder BundleMeshFinder(const std::filesystem::path& directory) {
  return [directory](const std::string& filename) {
    return model_files::FindMeshFile(filename, directory);
  };
}

MeshFinder DiskMeshFinder(const std::filesystem::path& model_directory,
                          const std::vector<std::string>& package_path) {
  const model_files::MeshFileSearch search(
      model_directory.empty() ? std::filesystem::path(".") : model_directory,
      model_files::PackagePath(package_path));
  return [search](const std::string& filename) { return search.Find(filename).found; };
}

}  // namespace mbstream::viewer
