#include "server/runs/model_registry.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <filesystem>
#include <set>

#include "server/kinematics/loop_coordinates.h"
#include "server/parse/asset_references.h"
#include "server/parse/import_cancel.h"
#include "server/parse/model_file.h"
#include "server/parse/sdf_import.h"
#include "server/parse/urdf_import.h"
#include "server/runs/model_id.h"
#include "server/runs/request_error.h"
#include "server/runs/unix_time.h"
#include "server/store/store.h"
#include "server/wire/bundle_mesh_source.h"
#include "server/wire/model_bundle_files.h"
#include "server/wire/model_info.h"
#include "shared/common/check.h"
#include "shared/common/utf8.h"

namespace mbstream {

namespace {

int64_t BundleBytes(const v1::ModelBundle& bundle) {
  int64_t bytes = static_cast<int64_t>(bundle.urdf().size() + bundle.scene_script().size());
  for (const v1::Asset& asset : bundle.assets()) bytes += asset.data().size() + asset.name().size();
  return bytes;
}

// The text fields are UTF-8 (a protobuf `string` holding anything else is stored but cannot
// be read back: found by start_run_fuzzer). Names the field, the line and the byte.
void ValidateText(const v1::ModelBundle& bundle) {
  const auto check = [](const std::string& field, const std::string& text) {
    const std::optional<std::size_t> bad = FirstInvalidUtf8(text);
    if (!bad) return;
    const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<long>(*bad), '\n');
    throw InputError(field + " is not UTF-8 text: line " + std::to_string(line) + ", byte " +
                     std::to_string(*bad) +
                     " starts no UTF-8 character; send UTF-8 text (a file in another "
                     "encoding: convert it, e.g. iconv -f latin1 -t utf-8)");
  };
  check("bundle.name", bundle.name());
  check("bundle.urdf", bundle.urdf());
  check("bundle.scene_script", bundle.scene_script());
  check("bundle.urdf_file_name", bundle.urdf_file_name());
  for (int i = 0; i < bundle.assets_size(); ++i) {
    check("bundle.assets[" + std::to_string(i) + "].name", bundle.assets(i).name());
  }
}

// Names (present, unique) and the per-asset limits, before anything is parsed.
void ValidateAssets(const v1::ModelBundle& bundle, const ServerLimits& limits) {
  if (bundle.assets_size() > limits.max_assets) {
    throw RequestError(RequestErrorKind::kResourceExhausted,
                       "the model bundle has " + std::to_string(bundle.assets_size()) +
                           " assets, more than this server's limit of " +
                           std::to_string(limits.max_assets) +
                           "; leave out meshes nothing draws or ask the operator to raise "
                           "--max-assets");
  }
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
    const int64_t bytes = static_cast<int64_t>(bundle.assets(i).data().size());
    if (bytes > limits.max_asset_bytes) {
      throw RequestError(RequestErrorKind::kResourceExhausted,
                         "asset '" + name + "' has " + std::to_string(bytes) +
                             " bytes, more than this server's limit of " +
                             std::to_string(limits.max_asset_bytes) +
                             " per asset; simplify the mesh or ask the operator to raise "
                             "--max-asset-mb");
    }
  }
}

std::string SourceName(const v1::ModelBundle& bundle) {
  return bundle.urdf_file_name().empty() ? std::string("model.urdf") : bundle.urdf_file_name();
}

// A bundle's model imported: URDF (with its <mimic> couplings when asked for), or SDFormat
// (told apart by content, as `mbstream simulate` does) with the joints that close its loops.
struct BundleImport {
  Model model;
  std::vector<LoopClosure> loops;
  std::vector<std::string> warnings;
  std::vector<std::string> mesh_files;
};

// Imports the bundle's model file (assets by name; their data is not needed) within the
// link limit (LimitError: RESOURCE_EXHAUSTED).
BundleImport ImportBundle(const v1::ModelBundle& bundle, const ServerLimits& limits) {
  const std::string source = SourceName(bundle);
  BundleImport result;
  if (DetectModelFormat(bundle.urdf()) == ModelFormat::kSdf) {
    SdfImport sdf = ImportSdf(bundle.urdf(), source,
                              SdfImportOptions{.max_links = limits.max_links,
                                               .collision_meshes = BundleMeshSource(bundle)});
    result.model = std::move(sdf.model);
    result.loops = std::move(sdf.loops);
    result.warnings = std::move(sdf.warnings);
    result.mesh_files = std::move(sdf.mesh_files);
    return result;
  }
  std::set<std::string> assets;
  for (const v1::Asset& asset : bundle.assets()) assets.insert(asset.name());
  UrdfImport urdf = ImportUrdf(bundle.urdf(), source, assets,
                               UrdfImportOptions{.repair = bundle.repair(),
                                                 .max_links = limits.max_links,
                                                 .couple_mimic = bundle.couple_mimic(),
                                                 .floating_base = bundle.floating_base(),
                                                 .collision_meshes = BundleMeshSource(bundle)});
  result.model = std::move(urdf.model);
  result.loops = std::move(urdf.loops);
  result.warnings = std::move(urdf.warnings);
  result.mesh_files = std::move(urdf.mesh_files);
  return result;
}

std::shared_ptr<CompiledModel> MakeCompiled(BundleImport import) {
  auto compiled = std::make_shared<CompiledModel>();
  compiled->model = std::move(import.model);
  compiled->loops = std::move(import.loops);
  compiled->joint_names = JointNames(compiled->model);
  compiled->result_joint_names = compiled->joint_names;
  for (std::string& name : LoopCoordinateNames(compiled->loops)) {
    compiled->result_joint_names.push_back(std::move(name));
  }
  return compiled;
}

// A submitted bundle checked and compiled: what is stored and the model.
struct Prepared {
  v1::ModelBundle bundle;  // without the assets nothing refers to
  std::shared_ptr<CompiledModel> compiled;
};

Prepared Prepare(const v1::ModelBundle& submitted, bool builtin, const ServerLimits& limits) {
  const int64_t bytes = BundleBytes(submitted);
  if (bytes > limits.max_model_bytes) {
    throw RequestError(RequestErrorKind::kResourceExhausted,
                       "the model bundle has " + std::to_string(bytes) +
                           " bytes, more than this server's limit of " +
                           std::to_string(limits.max_model_bytes) +
                           "; simplify the meshes or ask the operator to raise --max-model-mb");
  }
  if (submitted.urdf().empty()) {
    throw InputError("bundle.urdf is empty; send the URDF text of the model");
  }
  ValidateText(submitted);
  ValidateAssets(submitted, limits);
  BundleImport import = ImportBundle(submitted, limits);

  // Assets nothing refers to are dropped (not stored, not sent to viewers), with a warning:
  // `mbstream submit FOLDER` sends every mesh of the folder, so spare files are ordinary.
  Prepared prepared;
  prepared.bundle = submitted;
  std::vector<std::string> names;
  for (const v1::Asset& asset : submitted.assets()) names.push_back(asset.name());
  const std::vector<std::string> unreferenced =
      UnreferencedAssets(names, import.mesh_files, submitted.scene_script());
  if (!unreferenced.empty()) {
    const std::set<std::string> drop(unreferenced.begin(), unreferenced.end());
    prepared.bundle.clear_assets();
    for (const v1::Asset& asset : submitted.assets()) {
      if (drop.count(asset.name()) == 0) *prepared.bundle.add_assets() = asset;
    }
    for (const std::string& name : unreferenced) {
      import.warnings.push_back("asset '" + name +
                                "' is referenced by neither the model's meshes nor the scene "
                                "script's Part commands; it was not stored");
    }
  }
  const std::vector<std::string> warnings = import.warnings;
  prepared.compiled = MakeCompiled(std::move(import));
  v1::ModelInfo& info = prepared.compiled->info;
  DescribeModel(prepared.compiled->model, warnings, &info);
  info.set_id(ModelContentId(prepared.bundle));
  info.set_name(submitted.name().empty() ? prepared.compiled->model.name : submitted.name());
  prepared.bundle.set_name(info.name());
  info.set_has_scene(!submitted.scene_script().empty());
  info.set_num_assets(prepared.bundle.assets_size());
  int64_t asset_bytes = 0;
  for (const v1::Asset& asset : prepared.bundle.assets()) asset_bytes += asset.data().size();
  info.set_asset_bytes(asset_bytes);
  info.set_builtin(builtin);
  return prepared;
}

// "m-" and 24 hex digits (ModelContentId).
bool LooksLikeModelId(const std::string& text) {
  return text.size() == 26 && text.rfind("m-", 0) == 0 &&
         std::all_of(text.begin() + 2, text.end(),
                     [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; });
}

std::string MiB(int64_t bytes) { return std::to_string((bytes + (1 << 20) - 1) >> 20) + " MiB"; }

}  // namespace

ModelRegistry::ModelRegistry(Store* store, const ServerLimits& limits)
    : store_(store), limits_(limits) {
  MBSTREAM_CHECK(store_ != nullptr);
}

template <typename Wanted>
int ModelRegistry::LoadPending(const Wanted& wanted) const {
  int submitted = 0;
  std::unique_lock<std::mutex> lock(pending_mutex_);
  for (;;) {
    PendingBuiltin* next = nullptr;
    bool busy = false;  // a wanted one is being submitted by another thread
    for (PendingBuiltin& pending : pending_) {
      if (pending.done || !wanted(pending)) continue;
      if (!pending.compiling) {
        next = &pending;
        break;
      }
      busy = true;
    }
    if (next == nullptr) {
      if (!busy) return submitted;
      pending_done_.wait(lock);
      continue;
    }
    next->compiling = true;
    lock.unlock();
    try {
      // Known to the store already (an earlier start stored it): listed, not compiled.
      Register(ReadModelBundle(next->path, next->scene, {}, next->name), true);
      ++submitted;
    } catch (const ImportCancelled&) {
      // The server stops (or the caller went): the other built-ins are not read either, each
      // would take libsdformat's 0.1-0.2 s to notice (the stop took 2.3 s with eight left).
      lock.lock();
      next->compiling = false;
      pending_done_.notify_all();
      throw;
    } catch (const std::exception& e) {
      spdlog::warn("built-in model {} skipped: {}", next->path, e.what());
    }
    lock.lock();
    next->compiling = false;
    next->done = true;
    pending_done_.notify_all();
  }
}

void ModelRegistry::CheckCapacityLocked(int64_t bytes) const {
  int models = 0;
  int64_t total = 0;
  for (const auto& [id, entry] : by_id_) {
    if (entry.info.builtin()) continue;  // the operator's own models do not count
    ++models;
    total += entry.bytes;
  }
  if (models >= limits_.max_models) {
    throw RequestError(RequestErrorKind::kResourceExhausted,
                       "this server already stores " + std::to_string(models) +
                           " models, its limit; run an existing model (`mbstream models` lists "
                           "them) or ask the operator to raise --max-models");
  }
  if (total + bytes > limits_.max_total_model_bytes) {
    throw RequestError(RequestErrorKind::kResourceExhausted,
                       "storing this model (" + MiB(bytes) +
                           ") would take the server's models to " + MiB(total + bytes) +
                           ", more than its limit of " + MiB(limits_.max_total_model_bytes) +
                           "; simplify the meshes or ask the operator to raise --max-models-mb");
  }
}

v1::ModelInfo ModelRegistry::Submit(const v1::ModelBundle& bundle, bool builtin) {
  return Register(bundle, builtin);
}

v1::ModelInfo ModelRegistry::Register(const v1::ModelBundle& bundle, bool builtin) const {
  // The built-in models first, as at start: one of them may be this model (scripts/demo.sh
  // submits models/irb1600), or have its name (the newest model has it: see below).
  if (!builtin) LoadPendingBuiltins();
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto found = by_id_.find(ModelContentId(bundle));
    if (found != by_id_.end()) return found->second.info;
  }
  Prepared prepared = Prepare(bundle, builtin, limits_);
  v1::ModelInfo& info = prepared.compiled->info;
  const std::string id = info.id();
  const int64_t bytes = BundleBytes(prepared.bundle);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto found = by_id_.find(id);  // known without its spare assets, or submitted meanwhile
    if (found != by_id_.end()) return found->second.info;
    if (!builtin) CheckCapacityLocked(bytes);
    for (const auto& [other_id, other] : by_id_) {  // a name now means the newest model
      if (other.info.builtin() && other.info.name() == info.name() && !builtin) {
        info.add_warnings("the name '" + info.name() + "' was the built-in model " + other_id +
                          "'s; from now on it means this model, and the built-in stays " +
                          "reachable by its id " + other_id +
                          "; give another name (mbstream submit --name) to keep both");
      }
    }
    info.set_created_unix_ms(NowUnixMs());
    Entry& entry = by_id_[id];
    entry.info = info;
    entry.bytes = bytes;
    order_.push_back(id);
    CacheLocked(id, prepared.compiled);
  }
  try {
    store_->PutModel(info, prepared.bundle);  // not under the lock
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    by_id_.erase(id);
    order_.erase(std::remove(order_.begin(), order_.end(), id), order_.end());
    throw;
  }
  spdlog::info("model {} '{}' registered: {} dofs, {} links{}, {} warnings", id, info.name(),
               info.dofs(), info.links(), builtin ? " (built-in)" : "", info.warnings_size());
  return info;
}

int ModelRegistry::LoadStored() {
  const std::map<std::string, int64_t> sizes = store_->ModelBytes();
  int loaded = 0;
  std::lock_guard<std::mutex> lock(mutex_);
  for (const v1::ModelInfo& stored : store_->ListModels()) {
    Entry& entry = by_id_[stored.id()];
    if (!entry.info.id().empty()) continue;
    entry.info = stored;
    const auto size = sizes.find(stored.id());
    entry.bytes = size == sizes.end() ? 0 : size->second;
    order_.push_back(stored.id());
    ++loaded;
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
    // One model file (URDF or SDFormat): the folder is the model (with its scene and meshes).
    // Several: each is a model of its own, named after its file (models/linkages/*.sdf).
    std::vector<fs::path> urdfs;
    for (const fs::directory_entry& entry : fs::directory_iterator(dir)) {
      const fs::path extension = entry.path().extension();
      if (extension == ".urdf" || extension == ".sdf") urdfs.push_back(entry.path());
    }
    std::sort(urdfs.begin(), urdfs.end());
    struct Builtin {
      std::string path, name, scene;  // scene: NAME.scene beside a one-file model, or ""
    };
    std::vector<Builtin> models;
    if (urdfs.size() == 1) {
      models.push_back({dir.string(), dir.filename().string(), ""});
    } else {
      for (const fs::path& urdf : urdfs) {
        fs::path scene = urdf;
        scene.replace_extension(".scene");
        models.push_back({urdf.string(), urdf.stem().string(),
                          fs::is_regular_file(scene, error) ? scene.string() : ""});
      }
    }
    for (const auto& [path, name, scene] : models) {
      std::lock_guard<std::mutex> lock(pending_mutex_);
      pending_.push_back(PendingBuiltin{path, name, scene});
      ++loaded;
    }
  }
  return loaded;
}

int ModelRegistry::LoadPendingBuiltins() const {
  return LoadPending([](const PendingBuiltin&) { return true; });
}

void ModelRegistry::LoadPendingMatching(const std::string& id_or_name) const {
  LoadPending([&](const PendingBuiltin& p) { return p.name == id_or_name; });
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (by_id_.count(id_or_name) != 0) return;
    for (const std::string& id : order_) {
      if (by_id_.at(id).info.name() == id_or_name) return;
    }
  }
  // A model id (a client learns one only from a model registered, and so stored, by this
  // server or a replica of its store: RunManager::FindModel lists the store then) needs none;
  // a name nobody has gets the not-found error's list of every model, built-ins included.
  if (!LooksLikeModelId(id_or_name)) LoadPendingBuiltins();
}

const std::string& ModelRegistry::FindIdLocked(const std::string& id_or_name) const {
  auto found = by_id_.find(id_or_name);
  if (found != by_id_.end()) return found->first;
  for (auto it = order_.rbegin(); it != order_.rend(); ++it) {
    if (by_id_.at(*it).info.name() == id_or_name) return *it;
  }
  std::string known;
  for (const std::string& id : order_) {
    known += (known.empty() ? "" : ", ") + by_id_.at(id).info.name() + " (" + id + ")";
  }
  throw RequestError(RequestErrorKind::kNotFound,
                     "no model '" + id_or_name + "' on this server; known models: " +
                         (known.empty() ? "none" : known) + " (`mbstream models` lists them)");
}

std::shared_ptr<const CompiledModel> ModelRegistry::CacheLocked(
    const std::string& id, std::shared_ptr<const CompiledModel> compiled) const {
  Entry& entry = by_id_.at(id);
  if (entry.compiled == nullptr) entry.compiled = std::move(compiled);
  entry.last_use = ++use_clock_;
  for (;;) {
    int cached = 0;
    Entry* oldest = nullptr;
    for (auto& [other_id, other] : by_id_) {
      if (other.compiled == nullptr) continue;
      ++cached;
      if (oldest == nullptr || other.last_use < oldest->last_use) oldest = &other;
    }
    if (cached <= std::max(1, limits_.compiled_models_cached)) break;
    oldest->compiled.reset();  // runs using it keep their own reference
  }
  return entry.compiled;
}

std::shared_ptr<const CompiledModel> ModelRegistry::Find(const std::string& id_or_name) const {
  LoadPendingMatching(id_or_name);
  v1::ModelInfo info;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    Entry& entry = by_id_.at(FindIdLocked(id_or_name));
    if (entry.compiled != nullptr) {
      entry.last_use = ++use_clock_;
      return entry.compiled;
    }
    info = entry.info;
  }
  // Compile from the stored URDF, outside the lock (the assets' data is not read).
  std::optional<v1::ModelBundle> bundle = store_->GetModelBundle(info.id(), false);
  if (!bundle) {
    throw RequestError(RequestErrorKind::kNotFound,
                       "model " + info.id() +
                           " is listed but its bundle is not in the store; "
                           "submit the model again");
  }
  std::shared_ptr<CompiledModel> compiled;
  try {
    compiled = MakeCompiled(ImportBundle(*bundle, limits_));
  } catch (const std::exception& error) {
    spdlog::warn("stored model {} '{}' no longer compiles: {}", info.id(), info.name(),
                 error.what());
    throw RequestError(RequestErrorKind::kFailedPrecondition,
                       "stored model " + info.id() + " '" + info.name() +
                           "' no longer compiles with this server (" + error.what() +
                           "); fix the model and submit it again");
  }
  compiled->info = info;
  std::lock_guard<std::mutex> lock(mutex_);
  return CacheLocked(info.id(), std::move(compiled));
}

v1::ModelInfo ModelRegistry::Info(const std::string& id_or_name) const {
  LoadPendingMatching(id_or_name);
  std::lock_guard<std::mutex> lock(mutex_);
  return by_id_.at(FindIdLocked(id_or_name)).info;
}

v1::ModelBundle ModelRegistry::Bundle(const std::string& model_id) const {
  std::optional<v1::ModelBundle> bundle = store_->GetModelBundle(model_id, true);
  if (!bundle) {
    throw RequestError(RequestErrorKind::kNotFound,
                       "no model '" + model_id +
                           "' in this server's store; `mbstream models` "
                           "lists the models");
  }
  return *std::move(bundle);
}

std::vector<v1::ModelInfo> ModelRegistry::List() const {
  LoadPendingBuiltins();
  std::lock_guard<std::mutex> lock(mutex_);
  std::vector<v1::ModelInfo> list;
  for (const std::string& id : order_) list.push_back(by_id_.at(id).info);
  return list;
}

void ModelRegistry::Forget(const std::string& model_id) {
  std::lock_guard<std::mutex> lock(mutex_);
  by_id_.erase(model_id);
  order_.erase(std::remove(order_.begin(), order_.end(), model_id), order_.end());
}

int ModelRegistry::compiled_count() const {
  std::lock_guard<std::mutex> lock(mutex_);
  int count = 0;
  for (const auto& [id, entry] : by_id_) count += entry.compiled != nullptr ? 1 : 0;
  return count;
}

}  // namespace mbstream
