#include "server/service/status_from_exception.h"

#include <spdlog/spdlog.h>

#include "server/parse/import_cancel.h"
#include "server/runs/request_error.h"
#include "shared/common/check.h"

namespace mbstream {

grpc::Status StatusFromException(std::exception_ptr error) {
  try {
    std::rethrow_exception(error);
  } catch (const LimitError& e) {
    return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED, e.what());
  } catch (const InputError& e) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, e.what());
  } catch (const ImportCancelled& e) {
    return grpc::Status(grpc::StatusCode::UNAVAILABLE, e.what());
  } catch (const RequestError& e) {
    switch (e.kind()) {
      case RequestErrorKind::kNotFound:
        return grpc::Status(grpc::StatusCode::NOT_FOUND, e.what());
      case RequestErrorKind::kResourceExhausted:
        return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED, e.what());
      case RequestErrorKind::kFailedPrecondition:
        return grpc::Status(grpc::StatusCode::FAILED_PRECONDITION, e.what());
      case RequestErrorKind::kUnavailable:
        return grpc::Status(grpc::StatusCode::UNAVAILABLE, e.what());
    }
  } catch (const std::exception& e) {
    spdlog::error("internal error while serving a request: {}", e.what());
    return grpc::Status(
        grpc::StatusCode::INTERNAL,
        std::string("internal error (a bug in mbstream, please report it): ") + e.what());
  }
  return grpc::Status(grpc::StatusCode::INTERNAL, "unknown error");
}

}  // namespace mbstream
