#include "server/runs/model_registry.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <filesystem>
#include <set>

#include "server/common/check.h"
#include "server/parse/urdf_import.h"
#include "server/runs/model_id.h"
#include "server/runs/request_error.h"
#include "server/runs/unix_time.h"
#include "server/store/store.h"
#include "server/wire/model_bundle_files.h"
#include "server/wire/model_info.h"

namespace mbstream {

namespace {

int64_t BundleBytes(const v1::ModelBundle& bundle) {
  int64_t bytes = static_cast<int64_t>(bundle.urdf().size() + bundle.scene_script().size());
  for (const v1::Asset& asset : bundle.assets()) bytes += asset.data().size() + asset.name().size();
  return bytes;
}

void ValidateAssetNames(const v1::ModelBundle& bundle) {
  std::set<std::string> names;
  for (int i = 0; i < bundle.assets_size(); ++i) {
    const std::string& name = bundle.assets(i).name();
    if (name.empty()) {
      throw InputError("bundle.assets[" + std::to_string(i) +
                       "].name is empty; name each asset as the URDF or scene refers to it");
    }
    if (!names.insert(name).second) {
      throw InputError("bundle.assets[" + std::to_string(i) + "]: asset '" + name +
                       "' is given twice; send each file once");
    }
  }
}

}  // namespace

ModelRegistry::ModelRegistry(Store* store, const ServerLimits& limits)
    : store_(store), limits_(limits) {
  MBSTREAM_CHECK(store_ != nullptr);
}

std::shared_ptr<const CompiledModel> ModelRegistry::Compile(const v1::ModelBundle& bundle,
                                                            bool builtin, const std::string& id,
                                                            int64_t created_unix_ms) const {
  const int64_t bytes = BundleBytes(bundle);
  if (bytes > limits_.max_model_bytes) {
    throw RequestError(RequestErrorKind::kResourceExhausted,
                       "the model bundle has " + std::to_string(bytes) +
                           " bytes, more than this server's limit of " +
                           std::to_string(limits_.max_model_bytes) +
                           "; simplify the meshes or ask the operator to raise --max-model-mb");
  }
  if (bundle.urdf().empty()) {
    throw InputError("bundle.urdf is empty; send the URDF text of the model");
  }
  ValidateAssetNames(bundle);
  std::set<std::string> assets;
  for (const v1::Asset& asset : bundle.assets()) assets.insert(asset.name());
  const std::string source =
      bundle.urdf_file_name().empty() ? std::string("model.urdf") : bundle.urdf_file_name();
  UrdfImport import = ImportUrdf(bundle.urdf(), source, assets);
  const int links = static_cast<int>(import.model.frames.size());
  if (links > limits_.max_links) {
    throw RequestError(RequestErrorKind::kResourceExhausted,
                       source + ": the model has " + std::to_string(links) +
                           " links and points, more than this server's limit of " +
                           std::to_string(limits_.max_links) +
                           "; ask the operator to raise --max-links");
  }
  auto compiled = std::make_shared<CompiledModel>();
  compiled->bundle = bundle;
  compiled->model = std::move(import.model);
  compiled->joint_names = JointNames(compiled->model);
  v1::ModelInfo& info = compiled->info;
  DescribeModel(compiled->model, import.warnings, &info);
  info.set_id(id);
  info.set_name(bundle.name().empty() ? compiled->model.name : bundle.name());
  compiled->bundle.set_name(info.name());
  info.set_has_scene(!bundle.scene_script().empty());
  info.set_num_assets(bundle.assets_size());
  int64_t asset_bytes = 0;
  for (const v1::Asset& asset : bundle.assets()) asset_bytes += asset.data().size();
  info.set_asset_bytes(asset_bytes);
  info.set_builtin(builtin);
  info.set_created_unix_ms(created_unix_ms);
  return compiled;
}

std::shared_ptr<const CompiledModel> ModelRegistry::Submit(const v1::ModelBundle& bundle,
                                                           bool builtin) {
  const std::string id = ModelContentId(bundle);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto found = by_id_.find(id);
    if (found != by_id_.end()) return found->second;
  }
  std::shared_ptr<const CompiledModel> compiled = Compile(bundle, builtin, id, NowUnixMs());
  std::lock_guard<std::mutex> lock(mutex_);
  auto [it, inserted] = by_id_.emplace(id, compiled);
  if (!inserted) return it->second;  // submitted concurrently by another request
  order_.push_back(id);
  store_->PutModel(compiled->info, compiled->bundle);
  spdlog::info("model {} '{}' registered: {} dofs, {} links{}, {} warnings", id,
               compiled->info.name(), compiled->info.dofs(), compiled->info.links(),
               builtin ? " (built-in)" : "", compiled->info.warnings_size());
  return compiled;
}

int ModelRegistry::LoadStored() {
  int loaded = 0;
  for (const v1::ModelInfo& stored : store_->ListModels()) {
    std::optional<v1::ModelBundle> bundle = store_->GetModelBundle(stored.id());
    if (!bundle) continue;
    try {
      std::shared_ptr<const CompiledModel> compiled =
          Compile(*bundle, stored.builtin(), stored.id(), stored.created_unix_ms());
      std::lock_guard<std::mutex> lock(mutex_);
      if (by_id_.emplace(stored.id(), compiled).second) order_.push_back(stored.id());
      ++loaded;
    } catch (const std::exception& error) {
      spdlog::warn("stored model {} '{}' no longer compiles and is skipped: {}", stored.id(),
                   stored.name(), error.what());
    }
  }
  return loaded;
}

int ModelRegistry::LoadBuiltins(const std::string& directory) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(directory, error)) {
    spdlog::warn("built-in models directory {} does not exist; no built-in models", directory);
    return 0;
  }
  std::vector<fs::path> dirs;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory)) {
    if (entry.is_directory()) dirs.push_back(entry.path());
  }
  std::sort(dirs.begin(), dirs.end());
  int loaded = 0;
  for (const fs::path& dir : dirs) {
    // One URDF: the folder is the model (with its scene and meshes). Several: each URDF is
    // a model of its own, named after its file.
    std::vector<fs::path> urdfs;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
      if (entry.path().extension() == ".urdf") urdfs.push_back(entry.path());
    }
    std::sort(urdfs.begin(), urdfs.end());
    std::vector<std::pair<std::string, std::string>> models;  // path, name
    if (urdfs.size() == 1) {
      models.emplace_back(dir.string(), dir.filename().string());
    } else {
      for (const fs::path& urdf : urdfs) models.emplace_back(urdf.string(), urdf.stem().string());
    }
    for (const auto& [path, name] : models) {
      try {
        Submit(ReadModelBundle(path, "", {}, name), true);
        ++loaded;
      } catch (const std::exception& e) {
        spdlog::warn("built-in model {} skipped: {}", path, e.what());
      }
    }
  }
  return loaded;
}

std::shared_ptr<const CompiledModel> ModelRegistry::Find(const std::string& id_or_name) const {
  std::lock_guard<std::mutex> lock(mutex_);
  auto found = by_id_.find(id_or_name);
  if (found != by_id_.end()) return found->second;
  for (auto it = order_.rbegin(); it != order_.rend(); ++it) {
    const auto& model = by_id_.at(*it);
    if (model->info.name() == id_or_name) return model;
  }
  std::string known;
  for (const std::string& id : order_) {
    known += (known.empty() ? "" : ", ") + by_id_.at(id)->info.name() + " (" + id + ")";
  }
  throw RequestError(RequestErrorKind::kNotFound,
                     "no model '" + id_or_name + "' on this server; known models: " +
                         (known.empty() ? "none" : known) + " (`mbstream models` lists them)");
}

std::vector<v1::ModelInfo> ModelRegistry::List() const {
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<v1::ModelInfo> list;
  for (const std::string& id : order_) list.push_back(by_id_.at(id)->info);
  return list;
}

}  // namespace mbstream
