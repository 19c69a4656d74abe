// Cancelling a model's import: the importers poll ThrowIfImportCancelled() between their
// stages and every few hundred elements, so that a model that is slow to import (100,000
// links) is abandoned when its call is cancelled or the server stops. What cancels an import
// is the caller's, for the calling thread (ImportCancelScope: the service's SubmitModel
// passes its call's cancellation); CancelAllImports, the server's stop, cancels every import
// from then on. Outside a scope and before a stop, the checks cost one relaxed atomic load.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>

namespace mbstream {

// Thrown by ThrowIfImportCancelled: the service answers UNAVAILABLE
// (server/service/status_from_exception.cc), nothing of the model is stored. Its own type,
// not a RequestError: the import layer sits below the run manager that defines those.
class ImportCancelled : public std::runtime_error {
 public:
  explicit ImportCancelled(const std::string& why) : std::runtime_error(why) {}
};

// While alive, `cancelled` (called from this thread only, by its checks) cancels this
// thread's imports. Scopes nest: the innermost applies.
class ImportCancelScope {
 public:
  explicit ImportCancelScope(std::function<bool()> cancelled);
  ~ImportCancelScope();
  ImportCancelScope(const ImportCancelScope&) = delete;
  ImportCancelScope& operator=(const ImportCancelScope&) = delete;

 private:
  ImportCancelScope* outer_;
  std::function<bool()> cancelled_;
  friend void ThrowIfImportCancelled();
};

// The server is stopping: every import, running or to come, is cancelled. Irrevocable
// (a server that stops does not start again; tests use ResetImportCancelForTest).
void CancelAllImports();
void ResetImportCancelForTest();

// Throws ImportCancelled when the server stops or this thread's scope says so.
void ThrowIfImportCancelled();

// Calls ThrowIfImportCancelled every `every` calls of Tick (a loop over elements).
class ImportCancelPoll {
 public:
  explicit ImportCancelPoll(int every = 256) : every_(every) {}
  void Tick() {
    if (++count_ >= every_) {
      count_ = 0;
      ThrowIfImportCancelled();
    }
  }

 private:
  const int every_;
  int count_ = 0;
};

}  // namespace mbstream
