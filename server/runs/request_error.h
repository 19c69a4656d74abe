// Errors of a request to the server that are not about malformed input: what is asked for
// does not exist, exceeds a limit, or cannot be done in the current state. The service maps
// each kind to its gRPC status code (InputError -> INVALID_ARGUMENT). gRPC-free on purpose.
#pragma once

#include <stdexcept>
#include <string>

namespace mbstream {

enum class RequestErrorKind {
  kNotFound,            // NOT_FOUND: no model or run with that id/name
  kResourceExhausted,   // RESOURCE_EXHAUSTED: a server limit
  kFailedPrecondition,  // FAILED_PRECONDITION: e.g. the result of a run still running
  kUnavailable,         // UNAVAILABLE: the server is shutting down
};

class RequestError : public std::runtime_error {
 public:
  RequestError(RequestErrorKind kind, const std::string& message)
      : std::runtime_error(message), kind_(kind) {}
  RequestErrorKind kind() const { return kind_; }

 private:
  RequestErrorKind kind_;
};

// NOT_FOUND for a run id this server does not know, saying where the ids are listed.
inline RequestError UnknownRunError(const std::string& run_id) {
  return RequestError(RequestErrorKind::kNotFound,
                      "no run '" + run_id + "' on this server; `mbstream runs` lists them");
}

}  // namespace mbstream
