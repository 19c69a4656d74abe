"""gRPC channels to an mbstream server: insecure on loopback and unix sockets, TLS with a CA
file, and a bearer token sent as `authorization: Bearer <token>` on every call."""
import collections
import os
from typing import Optional, Tuple

import grpc

from .errors import bad_request

DEFAULT_ADDRESS = "127.0.0.1:50051"
MAX_MESSAGE_BYTES = 256 << 20  # like the C++ clients


def is_local_address(address: str) -> bool:
    """True for addresses that never leave this machine (unix sockets, loopback)."""
    return address.startswith(("unix:", "127.", "localhost:", "[::1]", "ipv4:127."))


def _read(path: str, what: str) -> bytes:
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError as error:
        raise bad_request("cannot read %s %s: %s" % (what, path,
                                                                          error.strerror))


def read_token_file(path: str) -> str:
    """The first word of the file's first line (a server token file's line is `TOKEN ROLES`)."""
    text = _read(path, "token file").decode("utf-8").splitlines()
    words = text[0].split() if text else []
    if not words:
        raise bad_request("token file %s is empty" % path)
    return words[0]


class _CallDetails(collections.namedtuple(
        "_CallDetails", ("method", "timeout", "metadata", "credentials", "wait_for_ready",
                         "compression")), grpc.ClientCallDetails):
    pass


class BearerTokenInterceptor(grpc.UnaryUnaryClientInterceptor, grpc.UnaryStreamClientInterceptor,
                             grpc.StreamUnaryClientInterceptor,
                             grpc.StreamStreamClientInterceptor):
    """Adds `authorization: Bearer <token>` to every call's metadata. An interceptor rather
    than call credentials, so that it works on insecure local channels too."""

    def __init__(self, token):
        self._header = ("authorization", "Bearer " + token)

    def _details(self, details):
        metadata = [m for m in (details.metadata or ()) if m[0] != "authorization"]
        metadata.append(self._header)
        return _CallDetails(details.method, details.timeout, metadata, details.credentials,
                            getattr(details, "wait_for_ready", None),
                            getattr(details, "compression", None))

    def intercept_unary_unary(self, continuation, details, request):
        return continuation(self._details(details), request)

    def intercept_unary_stream(self, continuation, details, request):
        return continuation(self._details(details), request)

    def intercept_stream_unary(self, continuation, details, requests):
        return continuation(self._details(details), requests)

    def intercept_stream_stream(self, continuation, details, requests):
        return continuation(self._details(details), requests)


def make_channel(address: Optional[str] = None, ca_file: Optional[str] = None,
                 token: Optional[str] = None, token_file: Optional[str] = None,
                 cert_file: Optional[str] = None,
                 key_file: Optional[str] = None) -> Tuple[str, grpc.Channel]:
    """A channel to `address` (host:port or unix:/path; default $MBSTREAM_SERVER or
    127.0.0.1:50051). With `ca_file`: TLS trusting that CA (PEM), optionally with a client
    certificate (`cert_file`, `key_file`). Without it: plaintext, and a token is then refused
    unless the address is local (loopback or unix socket)."""
    address = address or os.environ.get("MBSTREAM_SERVER") or DEFAULT_ADDRESS
    if token is None and token_file:
        token = read_token_file(token_file)
    options = [("grpc.max_receive_message_length", MAX_MESSAGE_BYTES),
               ("grpc.max_send_message_length", MAX_MESSAGE_BYTES)]
    if ca_file:
        credentials = grpc.ssl_channel_credentials(
            root_certificates=_read(ca_file, "CA file"),
            private_key=_read(key_file, "key file") if key_file else None,
            certificate_chain=_read(cert_file, "certificate file") if cert_file else None)
        channel = grpc.secure_channel(address, credentials, options=options)
    else:
        if token and not is_local_address(address):
            raise bad_request(
                "refusing to send a token in the clear to %s; give the "
                "server's CA with ca_file (TLS)" % address)
        channel = grpc.insecure_channel(address, options=options)
    if token:
        channel = grpc.intercept_channel(channel, BearerTokenInterceptor(token))
    return address, channel
