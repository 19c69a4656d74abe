#include "server/parse/model_file.h"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "server/parse/sdf_import.h"
#include "shared/model_files/mesh_file_search.h"

namespace mbstream {

ModelFileImport ImportModelFile(const std::string& path, const UrdfImportOptions& urdf_options,
                                const std::vector<std::string>& package_path) {
  std::ifstream in(path);
  std::ostringstream buffer;
  if (in) buffer << in.rdbuf();  // unreadable: the URDF reader says so, as it always has
  const std::string text = buffer.str();
  ModelFileImport result;
  result.format = DetectModelFormat(text);
  if (result.format == ModelFormat::kUrdf) {
    UrdfImport urdf = ImportUrdfFile(path, urdf_options);
    result.model = std::move(urdf.model);
    result.loops = std::move(urdf.loops);
    result.warnings = std::move(urdf.warnings);
  } else {
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    SdfImport sdf = ImportSdf(
        text, path,
        SdfImportOptions{
            .max_links = urdf_options.max_links,
            .includes = model_files::SdfIncludePath{dir.empty() ? "." : dir,
                                                    model_files::PackagePath(package_path)},
            .collision_meshes = DiskMeshSource(dir, package_path)});
    result.model = std::move(sdf.model);
    result.loops = std::move(sdf.loops);
    result.warnings = std::move(sdf.warnings);
  }
  return result;
}

}  // namespace mbstream
