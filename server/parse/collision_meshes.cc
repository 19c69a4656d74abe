#include "server/parse/collision_meshes.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>

#include "server/parse/convex_hull.h"
#include "shared/common/check.h"

namespace mbstream {

namespace {

// The vertices and triangles of one piece (a node's meshes).
struct MeshPiece {
  std::vector<Vector3d> vertices;
  std::vector<int> triangles;
};

void CollectPieces(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent,
                   const Vector3d& scale, std::vector<MeshPiece>* pieces) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  if (node.mNumMeshes > 0) {
    MeshPiece piece;
    for (unsigned m = 0; m < node.mNumMeshes; ++m) {
      const aiMesh& mesh = *scene.mMeshes[node.mMeshes[m]];
      const int first = static_cast<int>(piece.vertices.size());
      for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
        const aiVector3D p = transform * mesh.mVertices[v];
        piece.vertices.push_back(Vector3d(p.x, p.y, p.z).cwiseProduct(scale));
      }
      for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
        const aiFace& face = mesh.mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines enclose nothing
        for (int k = 0; k < 3; ++k) {
          piece.triangles.push_back(first + static_cast<int>(face.mIndices[k]));
        }
      }
    }
    if (!piece.vertices.empty()) pieces->push_back(std::move(piece));
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c) {
    CollectPieces(scene, *node.mChildren[c], transform, scale, pieces);
  }
}

std::string Extension(const std::string& file) {
  std::string extension = std::filesystem::path(file).extension().string();
  if (!extension.empty()) extension.erase(0, 1);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

}  // namespace

CollisionMesh ReadCollisionMesh(const std::string& bytes, const std::string& file,
                                const Vector3d& scale, const std::string& what) {
  if (!scale.allFinite() || (scale.array() == 0.0).any()) {
    throw InputError(what +
                     ": the scale has a zero or non-finite factor; give three finite "
                     "non-zero factors");
  }
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFileFromMemory(
      bytes.data(), bytes.size(),
      aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType,
      Extension(file).c_str());
  if (scene == nullptr || scene->mRootNode == nullptr) {
    const std::string why = importer.GetErrorString();
    throw InputError(what + ": cannot be read (" + (why.empty() ? "no scene" : why) +
                     "); give an STL, OBJ, Collada or glTF mesh Assimp reads");
  }
  std::vector<MeshPiece> pieces;
  CollectPieces(*scene, *scene->mRootNode, aiMatrix4x4(), scale, &pieces);
  size_t vertices = 0;
  for (const MeshPiece& piece : pieces) vertices += piece.vertices.size();
  if (vertices == 0) {
    throw InputError(what + ": the file holds no vertices; give a mesh with volume");
  }
  if (vertices > static_cast<size_t>(kMaxCollisionMeshVertices)) {
    throw InputError(what + ": " + std::to_string(vertices) + " vertices, more than " +
                     std::to_string(kMaxCollisionMeshVertices) +
                     " for a collision mesh; simplify it (or give its convex hull)");
  }
  CollisionMesh mesh;
  for (size_t k = 0; k < pieces.size(); ++k) {
    const std::string piece = pieces.size() > 1 ? what + ": piece " + std::to_string(k + 1) +
                                                      " of " + std::to_string(pieces.size())
                                                : what;
    ConvexPolytope hull = ConvexHullOf(pieces[k].vertices, piece);
    mesh.volume_ratio.push_back(MeshVolume(pieces[k].vertices, pieces[k].triangles) / hull.volume);
    mesh.pieces.push_back(std::move(hull));
  }
  return mesh;
}

}  // namespace mbstream
