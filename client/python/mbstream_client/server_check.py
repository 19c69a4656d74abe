"""What connect() checks: that a server answers and speaks this client's major version of the
wire protocol.

The wire's major version is the proto package, mbstream.v<N>: a server that speaks v1 serves
`mbstream.v1.Simulation`. mbstream-server enables gRPC server reflection
(grpc.reflection.v1alpha.ServerReflection), whose `list_services` names every service it
serves, so the client asks it once at connect. That needs no call of the Simulation service
itself (no token role, no server change) and tells a v2 server from a server that is not
mbstream at all. A server without reflection cannot be checked: the check passes with
`services` None.

The reflection messages are encoded by hand (three fields), so that the client needs no
generated reflection stubs (Debian ships no grpcio-reflection).
"""
import re
from dataclasses import dataclass
from typing import Any, Iterator, List, Optional, Tuple

import grpc

from ._stubs import SERVICE_NAME, WIRE_MAJOR
from .errors import IncompatibleServer, MbstreamError, make_error

REFLECTION_METHODS = ("/grpc.reflection.v1alpha.ServerReflection/ServerReflectionInfo",
                      "/grpc.reflection.v1.ServerReflection/ServerReflectionInfo")
# ServerReflectionRequest{list_services: ""}: field 7, length-delimited, empty.
LIST_SERVICES_REQUEST = b"\x3a\x00"
_SIMULATION = re.compile(r"^mbstream\.v(\d+)\.Simulation$")


@dataclass
class ServerCheck:
    """The outcome of connect()'s check. services: every service the server names (None when
    it has no reflection); wire_major: the major version of its Simulation service (None when
    unknown)."""
    services: Optional[List[str]]
    wire_major: Optional[int]


def _varint(data: bytes, at: int) -> Tuple[int, int]:
    value, shift = 0, 0
    while True:
        byte = data[at]
        at += 1
        value |= (byte & 0x7F) << shift
        if byte < 0x80:
            return value, at
        shift += 7


def _fields(data: bytes) -> Iterator[Tuple[int, Any]]:
    """(field number, value) of a protobuf message: int for varints, bytes otherwise."""
    at = 0
    while at < len(data):
        key, at = _varint(data, at)
        number, kind = key >> 3, key & 7
        if kind == 0:
            value, at = _varint(data, at)
            yield number, value
        elif kind == 2:
            size, at = _varint(data, at)
            yield number, data[at:at + size]
            at += size
        elif kind == 1:
            yield number, data[at:at + 8]
            at += 8
        elif kind == 5:
            yield number, data[at:at + 4]
            at += 4
        else:
            raise ValueError("unsupported wire type %d" % kind)


def parse_list_services(response: bytes) -> List[str]:
    """Service names from a ServerReflectionResponse (list_services_response = 6, its
    repeated ServiceResponse service = 1, whose name = 1); error_response = 7 raises."""
    names = []
    for number, value in _fields(response):
        if number == 6:
            for inner_number, service in _fields(value):
                if inner_number == 1:
                    for name_number, name in _fields(service):
                        if name_number == 1:
                            names.append(name.decode("utf-8"))
        elif number == 7:
            message = dict(_fields(value)).get(2, b"")
            raise ValueError("reflection error: %s" % message.decode("utf-8", "replace"))
    return names


def encode_list_services_response(names: List[str]) -> bytes:
    """The reverse of parse_list_services (for tests and stand-in servers)."""
    def length_delimited(number: int, payload: bytes) -> bytes:
        out, size = bytearray([(number << 3) | 2]), len(payload)
        while size >= 0x80:
            out.append((size & 0x7F) | 0x80)
            size >>= 7
        out.append(size)
        return bytes(out) + payload

    services = b"".join(length_delimited(1, length_delimited(1, n.encode("utf-8")))
                        for n in names)
    return length_delimited(6, services)


def list_services(channel: grpc.Channel, timeout_s: float) -> Optional[List[str]]:
    """The services the server names by reflection, or None when it has no reflection.
    Raises the matching MbstreamError (Unavailable when nothing answers)."""
    for method in REFLECTION_METHODS:
        call = channel.stream_stream(method)
        try:
            responses = call(iter([LIST_SERVICES_REQUEST]), timeout=timeout_s)
            for response in responses:
                return parse_list_services(response)
            return []
        except grpc.RpcError as error:
            code = error.code()
            if code == grpc.StatusCode.UNIMPLEMENTED:
                continue  # that version of reflection is absent: try the next one
            raise make_error(code.name if code else "UNKNOWN", error.details() or "",
                             code) from None
    return None


def check_server(channel: grpc.Channel, address: str, timeout_s: float,
                 client_version: str) -> ServerCheck:
    """Raises Unavailable when no server answers at `address` within timeout_s, and
    IncompatibleServer when it serves no mbstream.v{WIRE_MAJOR}.Simulation."""
    try:
        services = list_services(channel, timeout_s)
    except MbstreamError as error:
        if error.code in ("UNAVAILABLE", "DEADLINE_EXCEEDED"):
            raise make_error("UNAVAILABLE", "no mbstream server answers at %s (%s): start one "
                             "(mbstream-server --listen %s) or give the right address, and "
                             "for a TLS server its CA (ca_file)"
                             % (address, error.message, address), error.status) from None
        raise
    if services is None:
        return ServerCheck(None, None)
    if SERVICE_NAME in services:
        return ServerCheck(services, WIRE_MAJOR)
    majors = sorted(int(m.group(1)) for m in map(_SIMULATION.match, services) if m)
    if majors:
        raise IncompatibleServer(
            "FAILED_PRECONDITION",
            "the server at %s speaks the mbstream wire protocol v%s (service %s); this "
            "mbstream_client %s speaks v%d (%s): install the Python client from the server's "
            "release (pip install ./client/python of its checkout)"
            % (address, ", v".join(map(str, majors)),
               ", ".join("mbstream.v%d.Simulation" % m for m in majors), client_version,
               WIRE_MAJOR, SERVICE_NAME))
    raise IncompatibleServer(
        "FAILED_PRECONDITION",
        "the server at %s is not an mbstream server: it serves %s, not %s; check the address"
        % (address, ", ".join(services) or "no services", SERVICE_NAME))
