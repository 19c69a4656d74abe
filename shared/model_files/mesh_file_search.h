// Where `mbstream submit` and the viewer's local mode (`mbstream-viewer --model FILE`) find
// the file of a URDF <mesh filename> (or an SDFormat <mesh><uri>) on the user's disk, the
// way ROS users expect: relative paths from the URDF's folder; package://PKG/REST in the
// package path (folders whose package.xml names PKG, or named PKG), then REST relative to
// each of the URDF's ancestors (robot folders are often renamed); model://MODEL/REST alike,
// and first MODEL/REST beside the file or an ancestor (a world's model folders,
// sdf_includes.h); file:// as a file.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace mbstream::model_files {

struct MeshSearch {
  std::filesystem::path found;               // empty when not found
  std::vector<std::filesystem::path> tried;  // every place looked at, in order
  std::string note;  // for package://PKG when no package folder was found: where it was looked for
};

class MeshFileSearch {
 public:
  // `urdf_dir`: the URDF's folder. `package_path`: folders searched (with their
  // subfolders) for ROS packages, in order.
  MeshFileSearch(std::filesystem::path urdf_dir, std::vector<std::filesystem::path> package_path);

  MeshSearch Find(const std::string& filename) const;

 private:
  // The package folders named `package` (package.xml <name> or folder name), in order.
  std::vector<std::filesystem::path> PackageFolders(const std::string& package) const;

  std::filesystem::path urdf_dir_;
  std::vector<std::filesystem::path> package_path_;
};

// The folders below the `package_path` entries (at most 6 levels down, in order) whose
// package.xml names `package` or whose name is `package`.
std::vector<std::filesystem::path> PackageFolders(
    const std::vector<std::filesystem::path>& package_path, const std::string& package);

// The package path from `--package-path` flags followed by $MBSTREAM_PACKAGE_PATH (colon
// separated, empty entries skipped).
std::vector<std::filesystem::path> PackagePath(const std::vector<std::string>& flags);

}  // namespace mbstream::model_files
