// Reads a mesh file with Assimp (Collada, Wavefront OBJ with its .mtl, STL binary and ASCII,
// glTF/GLB, PLY and Assimp's other formats) into VTK surfaces, one per material.
//
// Coordinates are the file's, in metres: a Collada <unit meter="..."> is applied; its
// <up_axis> is not (the mesh stays in the URDF link's axes, as rviz draws it: published
// robot descriptions are authored and checked there, and some mark Y_UP meshes that rviz
// draws unrotated). Other formats carry no unit and are taken as metres.
#pragma once

#include <filesystem>
#include <optional>
#include <vector>

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <Eigen/Core>

namespace mbstream::viewer {

struct MeshSurface {
  // Points and triangles (no normals); with `texture`, texture coordinates too.
  vtkSmartPointer<vtkPolyData> triangles;
  std::optional<Eigen::Vector3d> colour;  // the material's diffuse colour, if it has one
  // The material's opacity, 0 (invisible) to 1 (opaque; also when the file gives none). A
  // Collada <transparent>/<transparency> pair is read by its opaque mode, as the
  // specification says (1.4.1, "Determining Transparency"): A_ONE (the default) takes
  // transparent's alpha times transparency, RGB_ZERO one less the luminance of its colour
  // times transparency, so <transparency>1</transparency> under A_ONE and 0.0 under RGB_ZERO
  // are both opaque. Assimp computes it so (AI_MATKEY_OPACITY; mesh_look_test checks both).
  double opacity = 1.0;
  // The material's diffuse texture (an image file: PNG, JPEG, ...), when it has one beside
  // the mesh and the surface has texture coordinates: drawn with it (its colour, not
  // `colour`, which such files often leave black). Empty otherwise.
  std::filesystem::path texture;
};

struct MeshFileContents {
  std::vector<MeshSurface> surfaces;  // one per material that has triangles
  long long triangle_count = 0;       // after decimation
  long long file_triangle_count = 0;  // as read
  // A material has a texture that cannot be drawn (embedded in the file, not found, or no
  // texture coordinates): its surface shows its colour.
  bool textured = false;
};

// Throws SceneError naming the file and Assimp's message when it cannot be read or holds
// no triangles.
MeshFileContents ReadMeshFile(const std::filesystem::path& path);

// `contents` with its surfaces decimated to about `max_triangles` in all (quadric
// clustering: the outline stays within a grid cell of about extent / sqrt(triangles));
// unchanged when it has no more. Textured surfaces are kept as they are (their texture
// coordinates would not survive clustering).
MeshFileContents Decimate(const MeshFileContents& contents, long long max_triangles);

}  // namespace mbstream::viewer
