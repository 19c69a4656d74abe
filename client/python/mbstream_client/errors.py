"""The client's exceptions: one class per gRPC status code that a caller may want to catch,
all subclasses of MbstreamError, each with the gRPC code name and the server's message.

    try:
        server.run("nosuch")
    except mbstream_client.NotFound as error:
        print(error.code, error.message)      # NOT_FOUND no model 'nosuch' ...
"""
from types import TracebackType
from typing import Dict, Literal, Optional, Type

import grpc


class MbstreamError(Exception):
    """A failed call or a bad input; the base of every exception of the client.

    code:    the gRPC status code name, e.g. "INVALID_ARGUMENT", "NOT_FOUND", "UNAVAILABLE"
             (local input errors use "INVALID_ARGUMENT" too; a run that did not finish, with
             Run.result(check=True), uses its state name, e.g. "CANCELLED", "DIVERGED")
    message: the server's message (or the client's, for local errors)
    status:  the grpc.StatusCode, or None when the error is not a gRPC status
    """

    code: str
    message: str
    status: Optional[grpc.StatusCode]

    def __init__(self, code: str, message: str, status: Optional[grpc.StatusCode] = None):
        super().__init__("%s: %s" % (code, message))
        self.code = code
        self.message = message
        self.status = status


class BadRequest(MbstreamError):
    """INVALID_ARGUMENT: a bad model, spec or argument (the message says which field)."""


class NotFound(MbstreamError):
    """NOT_FOUND: no such model or run."""


class AlreadyExists(MbstreamError):
    """ALREADY_EXISTS."""


class FailedPrecondition(MbstreamError):
    """FAILED_PRECONDITION: not now, e.g. the result of a run that is still running."""


class OutOfRange(MbstreamError):
    """OUT_OF_RANGE."""


class Unauthenticated(MbstreamError):
    """UNAUTHENTICATED: the server wants a token (connect(token=...)) or refused this one."""


class PermissionDenied(MbstreamError):
    """PERMISSION_DENIED: the token's roles do not allow this call."""


class ResourceExhausted(MbstreamError):
    """RESOURCE_EXHAUSTED: a server limit (runs queued, message size, budget)."""


class Unavailable(MbstreamError):
    """UNAVAILABLE: no server answers at the address, or the connection broke."""


class DeadlineExceeded(MbstreamError):
    """DEADLINE_EXCEEDED: the call took longer than its timeout."""


class Cancelled(MbstreamError):
    """CANCELLED: the call (not the run) was cancelled."""


class Unimplemented(MbstreamError):
    """UNIMPLEMENTED: the server does not have this call."""


class ServerError(MbstreamError):
    """INTERNAL, UNKNOWN, DATA_LOSS or ABORTED: the server failed; its message says how."""


class IncompatibleServer(MbstreamError):
    """The server speaks another major version of the wire protocol (or is not an mbstream
    server). Raised by connect(); code is "FAILED_PRECONDITION"."""


class RunFailed(MbstreamError):
    """A run that ended without finishing, from Run.result(check=True); code is the run's
    state name ("DIVERGED", "CANCELLED", ...), message the server's explanation."""


CLASS_OF_CODE: Dict[str, Type[MbstreamError]] = {
    "INVALID_ARGUMENT": BadRequest,
    "NOT_FOUND": NotFound,
    "ALREADY_EXISTS": AlreadyExists,
    "FAILED_PRECONDITION": FailedPrecondition,
    "OUT_OF_RANGE": OutOfRange,
    "UNAUTHENTICATED": Unauthenticated,
    "PERMISSION_DENIED": PermissionDenied,
    "RESOURCE_EXHAUSTED": ResourceExhausted,
    "UNAVAILABLE": Unavailable,
    "DEADLINE_EXCEEDED": DeadlineExceeded,
    "CANCELLED": Cancelled,
    "UNIMPLEMENTED": Unimplemented,
    "INTERNAL": ServerError,
    "UNKNOWN": ServerError,
    "DATA_LOSS": ServerError,
    "ABORTED": ServerError,
}


def make_error(code: str, message: str,
               status: Optional[grpc.StatusCode] = None) -> MbstreamError:
    """The exception of the class for `code` (MbstreamError itself for other codes)."""
    return CLASS_OF_CODE.get(code, MbstreamError)(code, message, status)


def bad_request(message: str) -> BadRequest:
    """A local input error (a missing file, a bad spec), shaped like the server's."""
    return BadRequest("INVALID_ARGUMENT", message)


def from_rpc_error(error: grpc.RpcError) -> MbstreamError:
    """The exception for a grpc.RpcError (a call's failure)."""
    status = error.code() if hasattr(error, "code") else None
    code = status.name if isinstance(status, grpc.StatusCode) else "UNKNOWN"
    message = error.details() if hasattr(error, "details") else str(error)
    return make_error(code, message or "", status)


class rpc_errors:
    """`with rpc_errors():` turns a grpc.RpcError into the matching MbstreamError."""

    def __enter__(self) -> "rpc_errors":
        return self

    def __exit__(self, kind: Optional[Type[BaseException]], value: Optional[BaseException],
                 traceback: Optional[TracebackType]) -> Literal[False]:
        if isinstance(value, grpc.RpcError):
            raise from_rpc_error(value) from None
        return False
