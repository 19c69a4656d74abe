#include "server/parse/import_cancel.h"

#include <atomic>
#include <utility>

namespace mbstream {

namespace {

std::atomic<bool> g_stopping{false};
thread_local ImportCancelScope* t_scope = nullptr;

}  // namespace

ImportCancelScope::ImportCancelScope(std::function<bool()> cancelled)
    : outer_(t_scope), cancelled_(std::move(cancelled)) {
  t_scope = this;
}

ImportCancelScope::~ImportCancelScope() { t_scope = outer_; }

void CancelAllImports() { g_stopping.store(true, std::memory_order_relaxed); }

void ResetImportCancelForTest() { g_stopping.store(false, std::memory_order_relaxed); }

void ThrowIfImportCancelled() {
  if (g_stopping.load(std::memory_order_relaxed)) {
    throw ImportCancelled(
        "the server is stopping: the model's import was abandoned and nothing of it stored; "
        "submit it again when the server is back");
  }
  if (t_scope != nullptr && t_scope->cancelled_ && t_scope->cancelled_()) {
    throw ImportCancelled(
        "the call was cancelled: the model's import was abandoned and nothing of it stored");
  }
}

}  // namespace mbstream
