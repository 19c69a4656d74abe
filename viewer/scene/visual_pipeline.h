// One visual part as a VTK pipeline: source (mesh polydata or STL reader) -> transform
// filter (scale and placement in its frame) -> triangles -> normals -> mapper -> actor.
// Built and updated once; afterwards only the actor's user matrix changes.
#pragma once

#include <vtkActor.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include "viewer/model/mesh.h"
#include "viewer/model/scene_description.h"

namespace mbstream::viewer {

vtkSmartPointer<vtkPolyData> PolyDataFromMesh(const Mesh& mesh);

// Throws SceneError naming the file when an STL file gives no triangles.
vtkSmartPointer<vtkActor> MakeVisualActor(const VisualPart& part);

// The surface of `part` as the actor shows it in its frame (metres): for tests and bounds.
vtkSmartPointer<vtkPolyData> VisualSurface(const VisualPart& part);

}  // namespace mbstream::viewer
