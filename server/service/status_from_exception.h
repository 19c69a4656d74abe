// The gRPC status of an exception thrown while serving a request.
#pragma once

#include <grpcpp/support/status.h>

#include <exception>

namespace mbstream {

// InputError -> INVALID_ARGUMENT, RequestError -> its kind's code (NOT_FOUND,
// RESOURCE_EXHAUSTED, FAILED_PRECONDITION, UNAVAILABLE), anything else -> INTERNAL (logged:
// a bug in mbstream). The message is the exception's text.
grpc::Status StatusFromException(std::exception_ptr error);

// Runs `body`, returning its status or the status of what it threw.
template <typename Body>
grpc::Status Serve(Body body) {
  try {
    return body();
  } catch (...) {
    return StatusFromException(std::current_exception());
  }
}

}  // namespace mbstream
