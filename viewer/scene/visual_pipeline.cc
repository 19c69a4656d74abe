#include "viewer/scene/visual_pipeline.h"

#include <vtkCellArray.h>
#include <vtkPoints.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkSTLReader.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkTriangleFilter.h>

#include "viewer/scene/scene_error.h"

namespace mbstream::viewer {

namespace {

vtkSmartPointer<vtkTransform> PlacementTransform(const VisualPart& part) {
  auto transform = vtkSmartPointer<vtkTransform>::New();
  transform->PostMultiply();
  transform->Scale(part.scale.x(), part.scale.y(), part.scale.z());
  double m[16];
  Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> view(m);
  view = part.placement.matrix();
  transform->Concatenate(m);
  return transform;
}

vtkSmartPointer<vtkPolyDataNormals> SurfacePipeline(const VisualPart& part) {
  auto place = vtkSmartPointer<vtkTransformPolyDataFilter>::New();
  place->SetTransform(PlacementTransform(part));
  if (const auto* stl = std::get_if<StlGeometry>(&part.geometry)) {
    auto reader = vtkSmartPointer<vtkSTLReader>::New();
    reader->SetFileName(stl->path.string().c_str());
    reader->Update();
    if (reader->GetOutput()->GetNumberOfCells() == 0) {
      throw SceneError(stl->path.string() + ": the STL file gives no triangles; replace it " +
                       "with a valid STL file");
    }
    place->SetInputConnection(reader->GetOutputPort());
  } else {
    place->SetInputData(PolyDataFromMesh(std::get<Mesh>(part.geometry)));
  }
  auto triangles = vtkSmartPointer<vtkTriangleFilter>::New();
  triangles->SetInputConnection(place->GetOutputPort());
  auto normals = vtkSmartPointer<vtkPolyDataNormals>::New();
  normals->SetInputConnection(triangles->GetOutputPort());
  normals->SetFeatureAngle(40);
  normals->SplittingOn();
  normals->ConsistencyOn();
  normals->AutoOrientNormalsOn();  // closed solids: outward, whatever the faces' order
  normals->Update();
  return normals;
}

}  // namespace

vtkSmartPointer<vtkPolyData> PolyDataFromMesh(const Mesh& mesh) {
  auto points = vtkSmartPointer<vtkPoints>::New();
  points->SetDataTypeToDouble();
  for (const Eigen::Vector3d& p : mesh.points) points->InsertNextPoint(p.x(), p.y(), p.z());
  auto polygons = vtkSmartPointer<vtkCellArray>::New();
  for (const std::vector<int>& face : mesh.faces) {
    polygons->InsertNextCell(static_cast<vtkIdType>(face.size()));
    for (int index : face) polygons->InsertCellPoint(index);
  }
  auto polydata = vtkSmartPointer<vtkPolyData>::New();
  polydata->SetPoints(points);
  polydata->SetPolys(polygons);
  return polydata;
}

vtkSmartPointer<vtkPolyData> VisualSurface(const VisualPart& part) {
  return SurfacePipeline(part)->GetOutput();
}

vtkSmartPointer<vtkActor> MakeVisualActor(const VisualPart& part) {
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputConnection(SurfacePipeline(part)->GetOutputPort());
  mapper->ScalarVisibilityOff();
  mapper->StaticOn();  // the geometry never changes: skip pipeline checks every frame
  auto actor = vtkSmartPointer<vtkActor>::New();
  actor->SetMapper(mapper);
  vtkProperty* property = actor->GetProperty();
  property->SetColor(part.color.x(), part.color.y(), part.color.z());
  property->SetAmbient(0.15);
  property->SetDiffuse(0.8);
  property->SetSpecular(0.25);
  property->SetSpecularPower(30);
  return actor;
}

}  // namespace mbstream::viewer
