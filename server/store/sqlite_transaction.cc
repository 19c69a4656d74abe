#include "server/store/sqlite_transaction.h"

#include <utility>

#include <sqlite3.h>

#include "server/store/sqlite_connection.h"

namespace mbstream {

SqliteTransaction::SqliteTransaction(SqliteConnection& connection, std::string operation)
    : connection_(connection), operation_(std::move(operation)) {
  connection_.Exec("BEGIN IMMEDIATE", "begin transaction for " + operation_);
}

SqliteTransaction::~SqliteTransaction() {
  // A failed statement may already have rolled the transaction back (e.g. SQLITE_FULL);
  // sqlite3_get_autocommit tells whether one is still open. Errors are ignored here: a
  // destructor must not throw, and the original exception is the one to report.
  if (open_ && sqlite3_get_autocommit(connection_.get()) == 0) {
    sqlite3_exec(connection_.get(), "ROLLBACK", nullptr, nullptr, nullptr);
  }
}

void SqliteTransaction::Commit() {
  connection_.Exec("COMMIT", "commit " + operation_);
  open_ = false;
}

}  // namespace mbstream
