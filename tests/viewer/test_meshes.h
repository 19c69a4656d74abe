// Small mesh files written by the tests themselves (no third-party meshes in the
// repository): an axis-aligned box from `low` to `high` in the file's units, in each format
// the viewer reads, with a material colour where the format has one.
#pragma once

#include <filesystem>
#include <string>

#include <Eigen/Geometry>

namespace mbstream::viewer::testing {

// Collada with <unit meter="`metres_per_unit`"> and <up_axis>`up_axis`</up_axis>, one
// material of diffuse colour `colour`.
void WriteColladaBox(const std::filesystem::path& path, const Eigen::Vector3d& low,
                     const Eigen::Vector3d& high, double metres_per_unit,
                     const std::string& up_axis, const Eigen::Vector3d& colour);

// Wavefront OBJ with a .mtl beside it (same stem): two boxes, the first from low to high
// with material "first" (Kd `colour_a`), the second shifted by +x (high - low) with material
// "second" (Kd `colour_b`).
void WriteObjBoxes(const std::filesystem::path& path, const Eigen::Vector3d& low,
                   const Eigen::Vector3d& high, const Eigen::Vector3d& colour_a,
                   const Eigen::Vector3d& colour_b);

// Binary (or ASCII) STL.
void WriteStlBox(const std::filesystem::path& path, const Eigen::Vector3d& low,
                 const Eigen::Vector3d& high, bool binary = true);

// glTF 2.0 with an embedded (base64) buffer and a material of base colour `colour`.
void WriteGltfBox(const std::filesystem::path& path, const Eigen::Vector3d& low,
                  const Eigen::Vector3d& high, const Eigen::Vector3d& colour);

// ASCII PLY without colour.
void WritePlyBox(const std::filesystem::path& path, const Eigen::Vector3d& low,
                 const Eigen::Vector3d& high);

}  // namespace mbstream::viewer::testing
