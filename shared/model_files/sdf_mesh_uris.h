// A mesh an included model names by a path relative to its own file (SDFormat allows it:
// `<uri>meshes/x.stl</uri>` in NAME/model.sdf), rewritten once the includes are read so that
// the world's reader finds it wherever the world is read from: `model://NAME/meshes/x.stl`
// when model://NAME finds that model's folder from the world (mesh_file_search.h), else the
// path relative to the world's folder when it lies below it, else file:///abs. `mbstream
// submit` then attaches it under NAME/meshes/x.stl (the expanded world names it so), the
// viewer's --model and `mbstream simulate` find it as they find a model:// mesh.
#pragma once

#include <filesystem>
#include <map>
#include <string>

#include <sdf/Element.hh>

#include "shared/model_files/sdf_includes.h"

namespace mbstream::model_files {

// The model folders an <include><uri>model://NAME</uri> was found at (absolute, normal),
// with their NAME.
using SdfIncludedModels = std::map<std::filesystem::path, std::string>;

// The URI for `uri`, written relative to `file` (an included model's file, as libsdformat
// names it), for a world read with `path`; `uri` itself when it is not a relative path
// (a scheme, an absolute path, empty).
std::string IncludedMeshUri(const std::string& uri, const std::filesystem::path& file,
                            const SdfIncludePath& path, const SdfIncludedModels& models);

// Rewrites each <mesh><uri> below `element` that an included file holds (its element's file
// path is a real file) and that is relative, as IncludedMeshUri says.
void RewriteIncludedMeshUris(const sdf::ElementPtr& element, const SdfIncludePath& path,
                             const SdfIncludedModels& models);

}  // namespace mbstream::model_files
