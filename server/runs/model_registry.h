// The server's models: compiled on first use, shared read-only by every run that uses them.
//
// The registry keeps every model's ModelInfo; a model's bundle (URDF, scene, assets) stays in
// the store. A model is compiled from its stored URDF when a run first needs it (not at
// start), and a bounded number of compiled models is cached (runs keep theirs alive).
// Built-in models the store does not know yet are read at start but compiled and stored when
// first asked for (by name, by id, or by a listing), so the server listens at once.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <list>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "mbstream/v1/model.pb.h"
#include "server/model/loop_closure.h"
#include "server/model/model.h"
#include "server/runs/server_limits.h"

namespace mbstream {

class Store;

// A model ready to run: its constant physics Model and its description. Its bundle is in
// the store (ModelRegistry::Bundle). An SDFormat model may close loops: `model` is then its
// spanning tree and `loops` the joints cut from it (server/model/loop_closure.h).
struct CompiledModel {
  v1::ModelInfo info;
  Model model;
  std::vector<LoopClosure> loops;        // empty for a tree (every URDF)
  std::vector<std::string> joint_names;  // the tree's joint order (drives, overrides)
  // The results' columns: the tree's joints, then the cut joints' coordinates
  // (server/kinematics/loop_coordinates.h); joint_names for a tree.
  std::vector<std::string> result_joint_names;
};

class ModelRegistry {
 public:
  // `store` (not owned, must outlive the registry) persists submitted models.
  ModelRegistry(Store* store, const ServerLimits& limits);

  // Compiles (URDF or SDFormat import, told apart by content, and validation) and stores `bundle`
  // unless it is already known; returns its info (the existing one when the content id is known).
  // Assets that neither the URDF nor the scene script refers to are dropped with a warning in the
  // info. Throws InputError with the importer's messages, RequestError(kResourceExhausted) when the
  // bundle exceeds the size or link limits, or (not for built-in models) when storing it
  // would exceed the server's model count or total size limits.
  v1::ModelInfo Submit(const v1::ModelBundle& bundle, bool builtin);

  // Lists the models of the store (at start) without compiling them; returns how many.
  int LoadStored();

  // Finds every model directory below `directory` (a folder with one .urdf or .sdf; see
  // ReadModelBundle; a folder with several: each file a model named after it): built-in
  // models, each read and submitted (compiled, unless the store has it from an earlier start)
  // when first asked for: by its name (Find, Info), by any listing, id or unknown name (List,
  // Find, Info), or by the first Submit, on the thread that asks. Returns how many were
  // found; a model that cannot be read or compiled is logged and skipped then.
  int LoadBuiltins(const std::string& directory);
  // Compiles and stores every built-in model still waiting (LoadBuiltins). Returns how many.
  int LoadPendingBuiltins() const;

  // By id, or by name (the newest with that name), compiled (from the store on first use).
  // Throws RequestError: kNotFound naming the known models, kFailedPrecondition when a
  // stored model no longer compiles.
  std::shared_ptr<const CompiledModel> Find(const std::string& id_or_name) const;

  // The info of a model by id or name, without compiling it. Throws as Find does.
  v1::ModelInfo Info(const std::string& id_or_name) const;

  // The whole bundle of model `model_id` (assets included), read from the store. Throws
  // RequestError(kNotFound).
  v1::ModelBundle Bundle(const std::string& model_id) const;

  std::vector<v1::ModelInfo> List() const;  // oldest first
  // Forgets model `model_id` (deleted from the store: run_deleter.h); runs that hold its
  // compiled model keep it until they end.
  void Forget(const std::string& model_id);

  // How many models are compiled and cached now (at most limits.compiled_models_cached).
  int compiled_count() const;

 private:
  // A built-in model found at start, not yet read or compiled (LoadBuiltins).
  struct PendingBuiltin {
    std::string path;        // the model file or folder
    std::string name;        // the folder's or the file's name
    std::string scene;       // NAME.scene beside a one-file model, or ""
    bool compiling = false;  // a thread is submitting it (pending_mutex_)
    bool done = false;       // submitted, or failed and logged
  };
  // Submits the waiting built-in models for which `wanted` is true, on this thread; waits for
  // those another thread is submitting. Neither mutex may be held by the caller.
  template <typename Wanted>
  int LoadPending(const Wanted& wanted) const;
  // The waiting built-in model named `id_or_name`; all of them when no model has that name
  // or id then.
  void LoadPendingMatching(const std::string& id_or_name) const;
  // Submit's body (mutable state only: a lazily loaded built-in is registered from const
  // lookups, as if it had been loaded at start).
  v1::ModelInfo Register(const v1::ModelBundle& bundle, bool builtin) const;
  struct Entry {
    v1::ModelInfo info;
    int64_t bytes = 0;                              // stored size (URDF, scene, assets)
    std::shared_ptr<const CompiledModel> compiled;  // null until first use, or evicted
    uint64_t last_use = 0;
  };
  // The entry for an id or a name (mutex_ held); throws RequestError(kNotFound).
  const std::string& FindIdLocked(const std::string& id_or_name) const;
  // Caches `compiled` for `id` and evicts the least recently used beyond the limit (mutex_
  // held). Returns the cached model (an earlier one if another thread was first).
  std::shared_ptr<const CompiledModel> CacheLocked(
      const std::string& id, std::shared_ptr<const CompiledModel> compiled) const;
  // Throws RequestError(kResourceExhausted) if one more user model of `bytes` would exceed
  // the count or total size limits (mutex_ held).
  void CheckCapacityLocked(int64_t bytes) const;

  Store* store_;
  ServerLimits limits_;
  mutable std::mutex mutex_;
  mutable std::map<std::string, Entry> by_id_;
  mutable std::vector<std::string> order_;  // ids, oldest first
  mutable uint64_t use_clock_ = 0;
  // Never locked while mutex_ is held.
  mutable std::mutex pending_mutex_;
  mutable std::condition_variable pending_done_;
  mutable std::list<PendingBuiltin> pending_;  // stable addresses; entries are never erased
};

}  // namespace mbstream
