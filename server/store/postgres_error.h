// The exception for PostgreSQL failures at runtime (the PostgresStore's SqliteError).
#pragma once

#include <string>

#include "shared/common/check.h"

namespace mbstream {

// A PostgreSQL call failed at runtime. It is an InternalError (the service reports it as an
// internal failure), naming the database (its URI without a password), the operation and
// PostgreSQL's message.
class PostgresError : public InternalError {
 public:
  using InternalError::InternalError;
};

// `message` without the trailing newline and spaces libpq ends its messages with.
std::string Trimmed(std::string message);

// Throws PostgresError for `operation` (e.g. "insert frames") on the database at `location`
// with the driver's message `detail`; adds what to do when the connection was lost.
[[noreturn]] void ThrowPostgresError(const std::string& location, const std::string& operation,
                                     const std::string& detail, bool connection_lost);

}  // namespace mbstream
