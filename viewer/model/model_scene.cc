#include "viewer/model/model_scene.h"

#include <fstream>
#include <sstream>

#include "common/check.h"
#include "urdf_reading/model_format.h"
#include "viewer/model/sdf_scene.h"
#include "viewer/model/urdf_scene.h"

namespace mbstream::viewer {

SceneDescription SceneFromModelText(const std::string& text, const std::string& source,
                                    const MeshFinder& find_mesh) {
  if (urdf_reading::DetectModelFormat(text) == urdf_reading::ModelFormat::kSdf) {
    return SceneFromSdf(text, source, find_mesh);
  }
  return SceneFromUrdf(text, source, find_mesh);
}

SceneDescription SceneFromModelFile(const std::filesystem::path& path,
                                    const std::vector<std::string>& package_path) {
  std::ifstream in(path, std::ios::binary);
  std::error_code error;
  if (!in || !std::filesystem::is_regular_file(path, error)) {
    throw InputError(path.string() + ": cannot read the model file; check the path");
  }
  std::ostringstream text;
  text << in.rdbuf();
  return SceneFromModelText(text.str(), path.string(),
                            DiskMeshFinder(path.parent_path(), package_path));
}

}  // namespace mbstream::viewer
