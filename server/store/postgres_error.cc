#include "server/store/postgres_error.h"

namespace mbstream {

std::string Trimmed(std::string message) {
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  return message;
}

void ThrowPostgresError(const std::string& location, const std::string& operation,
                        const std::string& detail, bool connection_lost) {
  std::string message = "store " + location + ": " + operation + " failed: " + Trimmed(detail);
  if (connection_lost) {
    message +=
        "; the connection to PostgreSQL was lost: check that the database server is "
        "running and reachable (the next call reconnects)";
  }
  throw PostgresError(message);
}

}  // namespace mbstream
