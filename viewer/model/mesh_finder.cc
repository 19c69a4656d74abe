#include "viewer/model/mesh_finder.h"

#include "urdf_reading/mesh_file_search.h"
#include "urdf_reading/mesh_lookup.h"

namespace mbstream::viewer {

MeshFinder BundleMeshFinder(const std::filesystem::path& directory) {
  return [directory](const std::string& filename) {
    return urdf_reading::FindMeshFile(filename, directory);
  };
}

MeshFinder DiskMeshFinder(const std::filesystem::path& model_directory,
                          const std::vector<std::string>& package_path) {
  const urdf_reading::MeshFileSearch search(
      model_directory.empty() ? std::filesystem::path(".") : model_directory,
      urdf_reading::PackagePath(package_path));
  return [search](const std::string& filename) { return search.Find(filename).found; };
}

}  // namespace mbstream::viewer
