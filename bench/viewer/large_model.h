// A generated robot the size of a PR2 (no third-party meshes): a base with four arms of
// `links_per_arm` revolute links each, every link a distinct binary STL tube of about
// `triangles / links` triangles, written with its URDF into a folder.
#pragma once

#include <filesystem>

namespace mbstream::viewer::bench {

struct LargeModel {
  std::filesystem::path urdf;
  int links = 0;
  long long triangles = 0;
};

LargeModel WriteLargeModel(const std::filesystem::path& dir, int arms, int links_per_arm,
                           long long triangles);

}  // namespace mbstream::viewer::bench
