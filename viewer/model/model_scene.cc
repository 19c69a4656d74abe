#include "viewer/model/model_scene.h"

#include <fstream>
#include <sstream>

#include "common/check.h"
#include "urdf_reading/mesh_file_search.h"
#include "urdf_reading/model_format.h"
#include "viewer/model/sdf_scene.h"
#include "viewer/model/urdf_scene.h"

namespace mbstream::viewer {

SceneDescription SceneFromModelText(const std::string& text, const std::string& source,
                                    const MeshFinder& find_mesh, bool floating_base) {
  if (urdf_reading::DetectModelFormat(text) == urdf_reading::ModelFormat::kSdf) {
    return SceneFromSdf(text, source, find_mesh);
  }
  return SceneFromUrdf(text, source, find_mesh, floating_base);
}

SceneDescription SceneFromModelFile(const std::filesystem::path& path,
                                    const std::vector<std::string>& package_path,
                                    bool floating_base) {
  std::ifstream in(path, std::ios::binary);
  std::error_code error;
  if (!in || !std::filesystem::is_regular_file(path, error)) {
    throw InputError(path.string() + ": cannot read the model file; check the path");
  }
  std::ostringstream text;
  text << in.rdbuf();
  const MeshFinder find_mesh = DiskMeshFinder(path.parent_path(), package_path);
  if (urdf_reading::DetectModelFormat(text.str()) == urdf_reading::ModelFormat::kSdf) {
    // On the user's disk an <include> is found beside the file and in the package path.
    urdf_reading::SdfIncludePath includes{path.parent_path().empty() ? "." : path.parent_path(),
                                          urdf_reading::PackagePath(package_path)};
    return SceneFromSdf(text.str(), path.string(), find_mesh, includes);
  }
  return SceneFromUrdf(text.str(), path.string(), find_mesh, floating_base);
}

}  // namespace mbstream::viewer
