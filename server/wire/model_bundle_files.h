// Model bundles from files: what `mbstream submit` sends and what the server loads from its
// built-in models directory.
#pragma once

#include <string>
#include <vector>

#include "mbstream/v1/model.pb.h"

namespace mbstream {

struct BundleFiles {
  // A URDF or SDFormat file (told apart by content), or a folder: its one *.urdf (directly
  // in it, else the one found below it), or without one its one *.sdf (likewise; a world's
  // folder: the one *.sdf holding a <world> directly in it), and its one *.scene (directly
  // in it), unless `scene_path` is given. An SDFormat file's <include>s are read here
  // (shared/model_files/sdf_includes.h: beside it, its ancestors, the package path) and sent
  // written into it: the server reads no file a model names.
  std::string model_path;
  std::string scene_path;                // scene script (may be empty)
  std::vector<std::string> asset_paths;  // more files, each added under its file name
  std::string name;                      // display name (may be empty)
  // Folders searched for package://PKG/... (before $MBSTREAM_PACKAGE_PATH).
  std::vector<std::string> package_paths;
  bool with_collision = false;  // attach collision meshes too
};

struct BundleRead {
  v1::ModelBundle bundle;
  // Meshes that were not found, each with every place tried (the server accepts a model
  // without its meshes; viewers draw placeholders).
  std::vector<std::string> warnings;
};

// Reads a bundle: the model file (in `urdf`, whichever its format), the scene, and every
// mesh the model's visuals (and collisions, when asked: URDF <mesh filename>, SDFormat
// <mesh><uri>, model:// found as package://) and the scene's Part commands refer to, found
// as MeshFileSearch does, each stored once under model_files::BundleAssetName of its
// reference (the path the model writes, so visual/a.stl and collision/a.stl do not collide). Throws
// InputError naming the path when a file cannot be read, a folder is ambiguous, or the model is a
// .xacro.
BundleRead ReadModelBundle(const BundleFiles& files);

// The same with no package path, visuals only, warnings dropped.
v1::ModelBundle ReadModelBundle(const std::string& model_path, const std::string& scene_path,
                                const std::vector<std::string>& asset_paths,
                                const std::string& name);

}  // namespace mbstream
