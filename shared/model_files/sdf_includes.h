// Where an SDFormat <include><uri> is found on the user's disk (`mbstream submit`,
// `mbstream simulate`, the viewer's --model), the way Gazebo users expect of model://NAME:
// a model folder NAME (its model.config names the model file; a folder with only a
// model.sdf will do) in the package path, else beside the including file or beside one of
// its ancestors. The server never resolves an include (it reads no file a model names):
// `mbstream submit` sends the world with its included models written into it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace mbstream::model_files {

struct SdfIncludePath {
  std::filesystem::path file_dir;                        // the including file's folder
  std::vector<std::filesystem::path> package_path = {};  // --package-path, $MBSTREAM_PACKAGE_PATH
};

struct SdfIncludeSearch {
  std::filesystem::path found;               // what libsdformat reads; empty: not found
  std::vector<std::filesystem::path> tried;  // every place looked at, in order
};

// model://NAME[/REST]: the folder NAME (a package path entry's subfolder named NAME, or
// whose package.xml names NAME, as mesh_file_search.h finds ROS packages; then NAME in
// file_dir and in each of its ancestors) holding a model.config or a model.sdf, then REST in
// it. file://ABS: that path. Anything else: a path relative to file_dir.
SdfIncludeSearch FindSdfInclude(const std::string& uri, const SdfIncludePath& path);

}  // namespace mbstream::model_files
