// The files a mesh file names besides itself: a Wavefront OBJ's `mtllib` materials and the
// images those name (map_Kd ...), a Collada's images (<library_images> <init_from>), a glTF's
// buffers and images ("uri"). `mbstream submit` attaches them beside the mesh so that a
// viewer following a submitted model's run draws its textures; the server keeps them.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace mbstream {

// The references `data` (the bytes of the mesh or material file `file_name`; its extension
// says the format: .obj, .mtl, .dae, .gltf) makes to other files, as written (file:// and
// %XX escapes undone, backslashes turned to slashes), in order, without repeats; embedded
// data (a glTF data: URI, a Collada image's inline data) and URLs are not references. Empty
// for other formats.
std::vector<std::string> MeshFileReferences(std::string_view file_name, std::string_view data);

// True if a file named `file_name` may name other files (MeshFileReferences reads it).
bool MayReferenceFiles(std::string_view file_name);

// True for a name with the extension of a file a mesh names: a material library (.mtl), an
// image (.png, .jpg, .jpeg, .bmp, .tga, .tif, .tiff, .gif, .dds, .ktx, .ktx2, .webp) or a
// glTF buffer (.bin); case-insensitive.
bool IsMeshCompanionName(std::string_view file_name);

// The asset name of the file `reference` (relative to the mesh's folder) names for a mesh
// stored under the asset name `mesh_asset`: "meshes/a.obj" and "../textures/t.png" give
// "textures/t.png". Empty when `reference` is absolute or would leave the bundle (the
// bundle holds relative paths only).
std::string CompanionAssetName(const std::string& mesh_asset, const std::string& reference);

}  // namespace mbstream
