#include "viewer/model/model_scene.h"

#include <fstream>
#include <sstream>

#include "shared/common/check.h"
#include "shared/model_files/mesh_file_search.h"
#include "shared/model_files/model_format.h"
#include "viewer/model/sdf_scene.h"
#include "viewer/model/urdf_scene.h"

namespace mbstream::viewer {

SceneDescription SceneFromModelText(const std::string& text, const std::string& source,
                                    const MeshFinder& find_mesh, bool floating_base) {
  if (model_files::DetectModelFormat(text) == model_files::ModelFormat::kSdf) {
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
  if (model_files::DetectModelFormat(text.str()) == model_files::ModelFormat::kSdf) {
    // On the user's disk an <include> is found beside the file and in the package path.
    model_files::SdfIncludePath includes{path.parent_path().empty() ? "." : path.parent_path(),
                                         model_files::PackagePath(package_path)};
    return SceneFromSdf(text.str(), path.string(), find_mesh, includes);
  }
  return SceneFromUrdf(text.str(), path.string(), find_mesh, floating_base);
}

}  // namespace mbstream::viewer
