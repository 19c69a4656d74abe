#include "viewer/scene/mesh_file_reader.h"

#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkPoints.h>
#include <vtkQuadricDecimation.h>
#include <assimp/Importer.hpp>

#include <cctype>
#include <map>
#include <string>

#include "viewer/scene/scene_error.h"

namespace mbstream::viewer {

namespace {

// STL and PLY carry no materials (Assimp gives them a default one); their colour
// extensions (per-vertex or per-facet colours) are not drawn.
bool HasMaterials(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension != ".stl" && extension != ".ply";
}

// The diffuse colour of `material`, unless it is Assimp's default material (a file without
// materials, such as an OBJ without .mtl).
std::optional<Eigen::Vector3d> DiffuseOf(const aiMaterial& material) {
  aiString name;
  if (material.Get(AI_MATKEY_NAME, name) == AI_SUCCESS &&
      std::string(name.C_Str()) == AI_DEFAULT_MATERIAL_NAME) {
    return std::nullopt;
  }
  aiColor4D colour;
  if (material.Get(AI_MATKEY_COLOR_DIFFUSE, colour) != AI_SUCCESS) return std::nullopt;
  return Eigen::Vector3d(colour.r, colour.g, colour.b).cwiseMax(0.0).cwiseMin(1.0);
}

bool Textured(const aiMaterial& material) {
  for (const aiTextureType type : {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR}) {
    if (material.GetTextureCount(type) > 0) return true;
  }
  return false;
}

vtkSmartPointer<vtkPolyData> Decimated(vtkPolyData* input, double keep_fraction) {
  vtkNew<vtkQuadricDecimation> decimate;
  decimate->SetInputData(input);
  decimate->SetTargetReduction(1.0 - keep_fraction);
  decimate->VolumePreservationOn();
  decimate->Update();
  vtkSmartPointer<vtkPolyData> output = decimate->GetOutput();
  return output;
}

}  // namespace

MeshFileContents ReadMeshFile(const std::filesystem::path& path, const MeshReadOptions& options) {
  Assimp::Importer importer;
  // Keep the file's axes (see the header); the unit scale stays in the root transform.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE,
                              aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  const aiScene* scene =
      importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                           aiProcess_PreTransformVertices | aiProcess_SortByPType |
                                           aiProcess_FindDegenerates | aiProcess_DropNormals);
  if (scene == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0) {
    throw SceneError(path.string() + ": the mesh file cannot be read (" +
                     importer.GetErrorString() +
                     "); give a Collada, OBJ, STL, glTF/GLB or PLY file");
  }
  // After PreTransformVertices every mesh is in the scene's frame, one per material.
  std::map<unsigned, std::pair<vtkSmartPointer<vtkPoints>, vtkSmartPointer<vtkCellArray>>>
      by_material;
  MeshFileContents contents;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh& mesh = *scene->mMeshes[m];
    if ((mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;
    auto& [points, triangles] = by_material[mesh.mMaterialIndex];
    if (!points) {
      points = vtkSmartPointer<vtkPoints>::New();
      points->SetDataTypeToFloat();
      triangles = vtkSmartPointer<vtkCellArray>::New();
    }
    const vtkIdType offset = points->GetNumberOfPoints();
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D& p = mesh.mVertices[v];
      points->InsertNextPoint(p.x, p.y, p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices != 3) continue;
      const vtkIdType ids[3] = {offset + face.mIndices[0], offset + face.mIndices[1],
                                offset + face.mIndices[2]};
      triangles->InsertNextCell(3, ids);
      ++contents.file_triangle_count;
    }
  }
  if (contents.file_triangle_count == 0) {
    throw SceneError(path.string() + ": the mesh file holds no triangles; give a file with a " +
                     "surface");
  }
  const double keep = options.decimate_above_triangles > 0 &&
                              contents.file_triangle_count > options.decimate_above_triangles
                          ? static_cast<double>(options.decimate_above_triangles) /
                                static_cast<double>(contents.file_triangle_count)
                          : 1.0;
  for (auto& [material, data] : by_material) {
    auto polydata = vtkSmartPointer<vtkPolyData>::New();
    polydata->SetPoints(data.first);
    polydata->SetPolys(data.second);
    if (keep < 1.0) polydata = Decimated(polydata, keep);
    MeshSurface surface;
    surface.triangles = polydata;
    if (material < scene->mNumMaterials) {
      if (HasMaterials(path)) surface.colour = DiffuseOf(*scene->mMaterials[material]);
      contents.textured = contents.textured || Textured(*scene->mMaterials[material]);
    }
    contents.triangle_count += polydata->GetNumberOfCells();
    contents.surfaces.push_back(std::move(surface));
  }
  return contents;
}

}  // namespace mbstream::viewer
