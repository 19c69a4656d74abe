#include "viewer/scene/mesh_file_reader.h"

#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkQuadricClustering.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
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

// The opacity of `material` (MeshSurface::opacity): Assimp's AI_MATKEY_OPACITY, which its
// Collada reader computes from <transparent> and <transparency> by the opaque mode; 1 when
// the material has none.
double OpacityOf(const aiMaterial& material) {
  float opacity = 1.0f;
  if (material.Get(AI_MATKEY_OPACITY, opacity) != AI_SUCCESS || !std::isfinite(opacity)) {
    return 1.0;
  }
  return std::clamp(static_cast<double>(opacity), 0.0, 1.0);
}

bool Textured(const aiMaterial& material) {
  for (const aiTextureType type : {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR}) {
    if (material.GetTextureCount(type) > 0) return true;
  }
  return false;
}

// The image file of `material`'s diffuse (or base colour) texture, found beside the mesh
// file `mesh`; empty when it has none, or it is embedded ("*0") or not there.
std::filesystem::path TextureFile(const aiMaterial& material, const std::filesystem::path& mesh) {
  for (const aiTextureType type : {aiTextureType_DIFFUSE, aiTextureType_BASE_COLOR}) {
    aiString file;
    if (material.GetTextureCount(type) == 0 || material.GetTexture(type, 0, &file) != AI_SUCCESS) {
      continue;
    }
    std::string name = file.C_Str();
    if (name.empty() || name[0] == '*') return {};  // embedded
    if (name.rfind("file://", 0) == 0) name = name.substr(7);
    std::replace(name.begin(), name.end(), '\\', '/');
    std::filesystem::path path(name);
    if (path.is_relative()) path = mesh.parent_path() / path;
    std::error_code error;
    if (std::filesystem::is_regular_file(path, error)) return path;
    // Exported files often name a folder of the author's machine: try the name alone.
    path = mesh.parent_path() / std::filesystem::path(name).filename();
    if (std::filesystem::is_regular_file(path, error)) return path;
    return {};
  }
  return {};
}

// About `target` triangles of `input` by quadric clustering: vertices are merged per
// cell of a grid over the bounds, each placed where it keeps the surface best (the
// quadric error), so the outline stays within a cell; linear in the input, unlike
// edge-collapse decimation (about 10x slower here). The grid is refined until the count
// is near the target.
vtkSmartPointer<vtkPolyData> Decimated(vtkPolyData* input, long long target) {
  double bounds[6];
  input->GetBounds(bounds);
  const double extent =
      std::max({bounds[1] - bounds[0], bounds[3] - bounds[2], bounds[5] - bounds[4], 1e-9});
  // A surface of area A gives about 2 A / h^2 triangles on a grid of spacing h; start from
  // a sphere-like guess A = 2 extent^2 and correct from the count.
  double divisions = std::sqrt(static_cast<double>(target));
  vtkSmartPointer<vtkPolyData> best;
  for (int attempt = 0; attempt < 4; ++attempt) {
    vtkNew<vtkQuadricClustering> cluster;
    cluster->SetInputData(input);
    cluster->AutoAdjustNumberOfDivisionsOff();
    const auto n = [&](int axis) {
      const double side = bounds[2 * axis + 1] - bounds[2 * axis];
      return std::max(2, static_cast<int>(std::ceil(divisions * side / extent)));
    };
    cluster->SetNumberOfDivisions(n(0), n(1), n(2));
    cluster->UseInputPointsOff();
    cluster->Update();
    best = cluster->GetOutput();
    const double count = static_cast<double>(best->GetNumberOfCells());
    if (count <= 1.25 * static_cast<double>(target) && count >= 0.6 * static_cast<double>(target)) {
      break;
    }
    if (count <= 0) break;
    divisions *= std::sqrt(static_cast<double>(target) / count);
  }
  if (best->GetNumberOfCells() == 0 || best->GetNumberOfCells() >= input->GetNumberOfCells()) {
    return input;  // nothing gained
  }
  return best;
}

// The triangles of one mesh of a material, a texture's coordinates with them.
struct Gathered {
  vtkSmartPointer<vtkPoints> points;
  vtkSmartPointer<vtkCellArray> triangles;
  std::filesystem::path texture;
  vtkSmartPointer<vtkFloatArray> uv;  // with a texture
};

// Appends `mesh`'s vertices and triangles to `gathered`; returns how many triangles.
long long Append(const aiMesh& mesh, Gathered& gathered) {
  long long appended = 0;
  vtkPoints* points = gathered.points;
  vtkCellArray* triangles = gathered.triangles;
  const vtkIdType offset = points->GetNumberOfPoints();
  for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
    const aiVector3D& p = mesh.mVertices[v];
    points->InsertNextPoint(p.x, p.y, p.z);
    if (gathered.uv) {
      const aiVector3D uv = mesh.HasTextureCoords(0) ? mesh.mTextureCoords[0][v] : aiVector3D();
      const float tuple[2] = {uv.x, uv.y};
      gathered.uv->InsertNextTypedTuple(tuple);
    }
  }
  for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
    const aiFace& face = mesh.mFaces[f];
    if (face.mNumIndices != 3) continue;
    const vtkIdType ids[3] = {offset + face.mIndices[0], offset + face.mIndices[1],
                              offset + face.mIndices[2]};
    triangles->InsertNextCell(3, ids);
    ++appended;
  }
  return appended;
}

}  // namespace

MeshFileContents ReadMeshFile(const std::filesystem::path& path) {
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
  std::map<unsigned, Gathered> by_material;
  MeshFileContents contents;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh& mesh = *scene->mMeshes[m];
    if ((mesh.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;
    Gathered& gathered = by_material[mesh.mMaterialIndex];
    if (!gathered.points) {
      gathered.points = vtkSmartPointer<vtkPoints>::New();
      gathered.points->SetDataTypeToFloat();
      gathered.triangles = vtkSmartPointer<vtkCellArray>::New();
      if (mesh.mMaterialIndex < scene->mNumMaterials && HasMaterials(path)) {
        gathered.texture = TextureFile(*scene->mMaterials[mesh.mMaterialIndex], path);
      }
      if (!gathered.texture.empty()) {
        gathered.uv = vtkSmartPointer<vtkFloatArray>::New();
        gathered.uv->SetName("TCoords");
        gathered.uv->SetNumberOfComponents(2);
      }
    }
    contents.file_triangle_count += Append(mesh, gathered);
  }
  if (contents.file_triangle_count == 0) {
    throw SceneError(path.string() + ": the mesh file holds no triangles; give a file with a " +
                     "surface");
  }
  for (auto& [material, data] : by_material) {
    auto polydata = vtkSmartPointer<vtkPolyData>::New();
    polydata->SetPoints(data.points);
    polydata->SetPolys(data.triangles);
    MeshSurface surface;
    surface.triangles = polydata;
    if (data.uv) {
      polydata->GetPointData()->SetTCoords(data.uv);
      surface.texture = data.texture;
    }
    if (material < scene->mNumMaterials) {
      if (HasMaterials(path)) {
        surface.colour = DiffuseOf(*scene->mMaterials[material]);
        surface.opacity = OpacityOf(*scene->mMaterials[material]);
      }
      contents.textured =
          contents.textured || (surface.texture.empty() && Textured(*scene->mMaterials[material]));
    }
    contents.triangle_count += polydata->GetNumberOfCells();
    contents.surfaces.push_back(std::move(surface));
  }
  return contents;
}

MeshFileContents Decimate(const MeshFileContents& contents, long long max_triangles) {
  if (max_triangles <= 0 || contents.triangle_count <= max_triangles) return contents;
  const double keep =
      static_cast<double>(max_triangles) / static_cast<double>(contents.triangle_count);
  MeshFileContents result = contents;
  result.triangle_count = 0;
  for (MeshSurface& surface : result.surfaces) {
    if (!surface.texture.empty()) {
      result.triangle_count += surface.triangles->GetNumberOfCells();
      continue;
    }
    const auto target = std::max<long long>(
        12,
        static_cast<long long>(keep * static_cast<double>(surface.triangles->GetNumberOfCells())));
    surface.triangles = Decimated(surface.triangles, target);
    result.triangle_count += surface.triangles->GetNumberOfCells();
  }
  return result;
}

}  // namespace mbstream::viewer
