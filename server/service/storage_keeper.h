// What an operator asks about the data (GetStorage, BackupStorage; `mbstream storage`,
// `mbstream backup`): the store's backend and place, the bytes its runs and models take, the
// free space against --min-free-mb, runs by state and what retention would delete; and a
// consistent copy of a live SQLite store (Store::Backup). The service calls it.
#pragma once

#include <string>

#include "mbstream/v1/simulation_service.pb.h"

namespace mbstream {

class Store;
class ModelRegistry;
class Retention;
class FreeSpaceWatch;

struct StorageSetup {
  Store* store = nullptr;
  bool sqlite = true;                     // else PostgreSQL
  std::string location;                   // the data directory, or the URI without password
  const ModelRegistry* models = nullptr;  // names of the models
  const Retention* retention = nullptr;   // null: no retention
  FreeSpaceWatch* free_space = nullptr;   // null: unknown (PostgreSQL)
};

class StorageKeeper {
 public:
  explicit StorageKeeper(StorageSetup setup) : setup_(std::move(setup)) {}

  // The report (reads the store; the free space is read again now).
  v1::GetStorageResponse Report() const;
  // Store::Backup into `dir`, timed. RequestError(kFailedPrecondition) on a PostgreSQL store.
  v1::BackupStorageResponse Backup(const std::string& dir) const;

 private:
  StorageSetup setup_;
};

}  // namespace mbstream
