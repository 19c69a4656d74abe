"""The one exception type of the client: a gRPC status code name and a message."""
import grpc


class MbstreamError(Exception):
    """A failed call or a bad input.

    code:    the gRPC status code name, e.g. "INVALID_ARGUMENT", "NOT_FOUND", "UNAVAILABLE"
             (local input errors use "INVALID_ARGUMENT" too; a run that did not finish, with
             Run.result(check=True), uses its state name, e.g. "CANCELLED", "DIVERGED")
    message: the server's message (or the client's, for local errors)
    status:  the grpc.StatusCode, or None when the error is not a gRPC status
    """

    def __init__(self, code, message, status=None):
        super().__init__("%s: %s" % (code, message))
        self.code = code
        self.message = message
        self.status = status


def from_rpc_error(error):
    """An MbstreamError for a grpc.RpcError (a call's failure)."""
    status = error.code() if hasattr(error, "code") else None
    code = status.name if isinstance(status, grpc.StatusCode) else "UNKNOWN"
    message = error.details() if hasattr(error, "details") else str(error)
    return MbstreamError(code, message or "", status)


class rpc_errors:
    """`with rpc_errors():` turns a grpc.RpcError into an MbstreamError."""

    def __enter__(self):
        return self

    def __exit__(self, kind, value, traceback):
        if isinstance(value, grpc.RpcError):
            raise from_rpc_error(value) from None
        return False
