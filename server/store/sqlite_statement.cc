#include "server/store/sqlite_statement.h"

#include <utility>

#include <sqlite3.h>

#include "server/store/sqlite_connection.h"
#include "server/store/sqlite_error.h"

namespace mbstream {

SqliteStatement::SqliteStatement(SqliteConnection& connection, const std::string& sql,
                                 std::string operation)
    : connection_(&connection), operation_(std::move(operation)) {
  // PERSISTENT: the statement lives as long as the store, so SQLite may allocate it from
  // longer-lived memory.
  const int rc = sqlite3_prepare_v3(connection.get(), sql.c_str(), static_cast<int>(sql.size()),
                                    SQLITE_PREPARE_PERSISTENT, &stmt_, nullptr);
  if (rc != SQLITE_OK) {
    ThrowSqliteError(connection.get(), rc, connection.path(), "prepare " + operation_);
  }
}

SqliteStatement::SqliteStatement(SqliteStatement&& other) noexcept
    : connection_(other.connection_),
      stmt_(std::exchange(other.stmt_, nullptr)),
      operation_(std::move(other.operation_)) {}

SqliteStatement::~SqliteStatement() {
  if (stmt_ != nullptr) sqlite3_finalize(stmt_);
}

namespace {
void CheckBind(int rc, const SqliteConnection& connection, const std::string& operation) {
  if (rc != SQLITE_OK) ThrowSqliteError(connection.get(), rc, connection.path(), operation);
}
}  // namespace

void SqliteStatement::BindInt64(int index, int64_t value) {
  CheckBind(sqlite3_bind_int64(stmt_, index, value), *connection_, "bind " + operation_);
}

void SqliteStatement::BindText(int index, std::string_view value) {
  CheckBind(
      sqlite3_bind_text64(stmt_, index, value.data(), value.size(), SQLITE_TRANSIENT, SQLITE_UTF8),
      *connection_, "bind " + operation_);
}

void SqliteStatement::BindBlob(int index, std::string_view value) {
  // A zero-length blob with a null pointer would bind NULL; "" keeps it an empty blob.
  const char* data = value.data() != nullptr ? value.data() : "";
  CheckBind(sqlite3_bind_blob64(stmt_, index, data, value.size(), SQLITE_STATIC), *connection_,
            "bind " + operation_);
}

bool SqliteStatement::Step() {
  const int rc = sqlite3_step(stmt_);
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  ThrowSqliteError(connection_->get(), rc, connection_->path(), operation_);
}

void SqliteStatement::Run() {
  while (Step()) {
  }
}

int64_t SqliteStatement::ColumnInt64(int column) const {
  return sqlite3_column_int64(stmt_, column);
}

bool SqliteStatement::ColumnIsNull(int column) const {
  return sqlite3_column_type(stmt_, column) == SQLITE_NULL;
}

std::string_view SqliteStatement::ColumnText(int column) const {
  const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(stmt_, column));
  const int size = sqlite3_column_bytes(stmt_, column);
  return text != nullptr ? std::string_view(text, static_cast<size_t>(size)) : std::string_view();
}

std::string_view SqliteStatement::ColumnBlob(int column) const {
  // column_blob before column_bytes, as SQLite's documentation asks.
  const auto* data = static_cast<const char*>(sqlite3_column_blob(stmt_, column));
  const int size = sqlite3_column_bytes(stmt_, column);
  return data != nullptr ? std::string_view(data, static_cast<size_t>(size)) : std::string_view();
}

void SqliteStatement::Reset() noexcept {
  sqlite3_reset(stmt_);
  sqlite3_clear_bindings(stmt_);
}

}  // namespace mbstream
