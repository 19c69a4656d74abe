#include "viewer/scene/visual_pipeline.h"

#include <spdlog/spdlog.h>
#include <vtkAppendPolyData.h>
#include <vtkCellArray.h>
#include <vtkImageData.h>
#include <vtkImageReader2.h>
#include <vtkImageReader2Factory.h>
#include <vtkPoints.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkTexture.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkTriangleFilter.h>

#include "viewer/scene/mesh_cache.h"
#include "viewer/scene/scene_error.h"

namespace mbstream::viewer {

void CopyToVtk(const Eigen::Isometry3d& t, vtkMatrix4x4* m) {
  double elements[16];
  Eigen::Map<Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> view(elements);
  view = t.matrix();
  m->DeepCopy(elements);  // marks the matrix modified: the actor re-reads it
}

namespace {

struct Surface {
  vtkSmartPointer<vtkPolyDataNormals> output;
  Eigen::Vector3d colour;
  std::filesystem::path texture;  // drawn with it (and white), when not empty
  double opacity = 1.0;           // the file material's (MeshSurface::opacity)
};

// The image file `path` as a texture (repeated, as OBJ and Collada texture coordinates
// may leave [0, 1]); null, with a warning, when no VTK reader takes it.
vtkSmartPointer<vtkTexture> ReadTexture(const std::filesystem::path& path) {
  vtkSmartPointer<vtkImageReader2> reader;
  reader.TakeReference(vtkImageReader2Factory::CreateImageReader2(path.string().c_str()));
  if (!reader) {
    spdlog::warn("{}: no image reader for this texture; its surface is drawn in its colour",
                 path.string());
    return nullptr;
  }
  reader->SetFileName(path.string().c_str());
  reader->Update();
  auto texture = vtkSmartPointer<vtkTexture>::New();
  texture->SetInputData(reader->GetOutput());
  texture->InterpolateOn();
  texture->RepeatOn();
  texture->MipmapOn();
  return texture;
}

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

// `input` placed, triangulated, with normals. Primitive and script meshes are closed solids
// whose faces may be written in either order: their normals are oriented outwards. A mesh
// file's triangles are taken as they are (large; lighting is two-sided).
vtkSmartPointer<vtkPolyDataNormals> Place(const VisualPart& part, vtkPolyData* input, bool orient) {
  auto place = vtkSmartPointer<vtkTransformPolyDataFilter>::New();
  place->SetTransform(PlacementTransform(part));
  place->SetInputData(input);
  auto normals = vtkSmartPointer<vtkPolyDataNormals>::New();
  if (orient) {
    auto triangles = vtkSmartPointer<vtkTriangleFilter>::New();
    triangles->SetInputConnection(place->GetOutputPort());
    normals->SetInputConnection(triangles->GetOutputPort());
  } else {
    normals->SetInputConnection(place->GetOutputPort());
  }
  normals->SetFeatureAngle(40);
  normals->SplittingOn();
  normals->SetConsistency(orient);
  normals->SetAutoOrientNormals(orient);
  normals->Update();
  return normals;
}

std::vector<Surface> Surfaces(const VisualPart& part, long long max_triangles,
                              VisualActors* stats) {
  std::vector<Surface> surfaces;
  if (const auto* file = std::get_if<MeshFile>(&part.geometry)) {
    const std::shared_ptr<const MeshFileContents> contents =
        CachedMeshFile(file->path, max_triangles);
    for (const MeshSurface& surface : contents->surfaces) {
      const bool own = file->file_colours && surface.colour.has_value();
      // The file's material opacity goes with its colours (MeshFile::file_colours).
      surfaces.push_back({Place(part, surface.triangles, false), own ? *surface.colour : part.color,
                          surface.texture, file->file_colours ? surface.opacity : 1.0});
    }
    if (stats) {
      stats->triangles += contents->triangle_count;
      stats->textured = stats->textured || contents->textured;
    }
  } else {
    vtkSmartPointer<vtkPolyData> mesh = PolyDataFromMesh(std::get<Mesh>(part.geometry));
    surfaces.push_back({Place(part, mesh, true), part.color, {}});
    if (stats) stats->triangles += surfaces.back().output->GetOutput()->GetNumberOfPolys();
  }
  return surfaces;
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

vtkSmartPointer<vtkPolyData> VisualSurface(const VisualPart& part, long long max_triangles) {
  vtkNew<vtkAppendPolyData> append;
  for (const Surface& surface : Surfaces(part, max_triangles, nullptr)) {
    append->AddInputData(surface.output->GetOutput());
  }
  append->Update();
  vtkSmartPointer<vtkPolyData> output = append->GetOutput();
  return output;
}

VisualActors MakeVisualActors(const VisualPart& part, long long max_triangles) {
  VisualActors result;
  for (const Surface& surface : Surfaces(part, max_triangles, &result)) {
    auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
    mapper->SetInputConnection(surface.output->GetOutputPort());
    mapper->ScalarVisibilityOff();
    mapper->StaticOn();  // the geometry never changes: skip pipeline checks every frame
    auto actor = vtkSmartPointer<vtkActor>::New();
    actor->SetMapper(mapper);
    vtkProperty* property = actor->GetProperty();
    property->SetColor(surface.colour.x(), surface.colour.y(), surface.colour.z());
    property->SetOpacity(part.opacity * surface.opacity);
    property->SetAmbient(0.15);
    property->SetDiffuse(0.8);
    property->SetSpecular(0.25);
    property->SetSpecularPower(30);
    if (!surface.texture.empty()) {
      if (vtkSmartPointer<vtkTexture> texture = ReadTexture(surface.texture)) {
        actor->SetTexture(texture);
        property->SetColor(1.0, 1.0, 1.0);  // the texture's colours, lit
        property->SetSpecular(0.1);
      } else {
        result.textured = true;
      }
    }
    result.actors.push_back(actor);
  }
  return result;
}

}  // namespace mbstream::viewer
