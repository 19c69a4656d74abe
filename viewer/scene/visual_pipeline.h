// One visual part as VTK pipelines: source (mesh polydata, or the surfaces of a mesh file,
// one per material) -> transform filter (scale and placement in its frame) -> triangles ->
// normals -> mapper -> actor. Built and updated once; afterwards only the actors' user
// matrices change.
#pragma once

#include <vector>

#include <vtkActor.h>
#include <vtkMatrix4x4.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <Eigen/Geometry>

#include "viewer/model/mesh.h"
#include "viewer/model/scene_description.h"
#include "viewer/scene/mesh_file_reader.h"

namespace mbstream::viewer {

vtkSmartPointer<vtkPolyData> PolyDataFromMesh(const Mesh& mesh);

// Writes a frame's pose into an actor's user matrix (marked modified: the actor re-reads it).
void CopyToVtk(const Eigen::Isometry3d& t, vtkMatrix4x4* m);

struct VisualActors {
  std::vector<vtkSmartPointer<vtkActor>> actors;  // one per surface
  long long triangles = 0;
  bool textured = false;  // the mesh file has textures that cannot be drawn (mesh_file_reader.h)
};

// Throws SceneError naming the file when a mesh file cannot be read or gives no triangles.
// Colours: a mesh file's own material colour per surface when part.file_colours and the
// material has one, else part.color; a surface with a texture (MeshSurface::texture) is
// drawn with it (a vtkTexture on its actor, the colour white), whatever the colours say.
// A mesh file is decimated to about `max_triangles` (0 = as read).
VisualActors MakeVisualActors(const VisualPart& part, long long max_triangles = 0);

// The surface of `part` as its actors show it in its frame (metres), all surfaces in one:
// for tests and bounds.
vtkSmartPointer<vtkPolyData> VisualSurface(const VisualPart& part, long long max_triangles = 0);

}  // namespace mbstream::viewer
