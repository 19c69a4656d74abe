#include "server/wire/bundle_mesh_source.h"

namespace mbstream {

MeshSource BundleMeshSource(const v1::ModelBundle& bundle) {
  return AssetMeshSource([&bundle](const std::string& name) -> const std::string* {
    for (const v1::Asset& asset : bundle.assets()) {
      if (asset.name() == name) return &asset.data();
    }
    return nullptr;
  });
}

}  // namespace mbstream
