// The server's models: compiled once, shared read-only by every run that uses them.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "mbstream/v1/model.pb.h"
#include "server/model/model.h"
#include "server/runs/server_limits.h"

namespace mbstream {

class Store;

// A model ready to run: its constant physics Model, its description and its bundle.
struct CompiledModel {
  v1::ModelInfo info;
  v1::ModelBundle bundle;
  Model model;
  std::vector<std::string> joint_names;  // the model's joint order
};

class ModelRegistry {
 public:
  // `store` (not owned, must outlive the registry) persists submitted models.
  ModelRegistry(Store* store, const ServerLimits& limits);

  // Compiles (URDF import and validation) and registers `bundle`; stores it unless it is
  // already known. Returns the model (the existing one when the content id is known).
  // Throws InputError with the importer's messages, RequestError(kResourceExhausted) when
  // the bundle exceeds the size or link limits.
  std::shared_ptr<const CompiledModel> Submit(const v1::ModelBundle& bundle, bool builtin);

  // Re-compiles every model of the store (at start). A stored model that no longer compiles
  // is skipped with a warning in the log; returns how many were loaded.
  int LoadStored();

  // Submits every model directory below `directory` (a folder with one .urdf; see
  // ReadModelBundle) as built-in. Returns how many; logs and skips ones that fail.
  int LoadBuiltins(const std::string& directory);

  // By id, or by name (the newest with that name). Throws RequestError(kNotFound) naming
  // the known models.
  std::shared_ptr<const CompiledModel> Find(const std::string& id_or_name) const;

  std::vector<v1::ModelInfo> List() const;  // oldest first

 private:
  std::shared_ptr<const CompiledModel> Compile(const v1::ModelBundle& bundle, bool builtin,
                                               const std::string& id,
                                               int64_t created_unix_ms) const;

  Store* store_;
  ServerLimits limits_;
  mutable std::mutex mutex_;
  std::map<std::string, std::shared_ptr<const CompiledModel>> by_id_;
  std::vector<std::string> order_;  // ids, oldest first
};

}  // namespace mbstream
