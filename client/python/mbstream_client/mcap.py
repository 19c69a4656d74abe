"""A stored run as one MCAP file (ROS 2's rosbag2 format, docs/mcap.md): the server writes it
(ExportMcap, the same writer as `mbstream result --mcap`) and this module saves its bytes as
they come, so a long run is never in memory."""
import datetime
import numbers
import os
from typing import Any, Optional, Union

from ._stubs import run_pb2, simulation_service_pb2 as service_pb2
from .errors import rpc_errors

StartLike = Union[None, str, float, int, datetime.datetime]

COMPRESSIONS = ("zstd", "lz4", "none")


def start_text(start: StartLike) -> str:
    """ExportMcapRequest.start of `start`: None (the run's start), a str as the CLI's
    --mcap-start takes it ("2026-11-26T12:00:00Z" or seconds since the Unix epoch), a number
    of seconds since the Unix epoch, or a datetime (a naive one is taken as UTC)."""
    if start is None:
        return ""
    if isinstance(start, str):
        return start
    if isinstance(start, datetime.datetime):
        if start.tzinfo is not None:
            start = start.astimezone(datetime.timezone.utc).replace(tzinfo=None)
        return start.strftime("%Y-%m-%dT%H:%M:%S") + (".%06d" % start.microsecond) + "Z"
    if isinstance(start, numbers.Real) and not isinstance(start, bool):
        return repr(float(start))
    raise TypeError("start must be None, a str, seconds since the Unix epoch or a datetime, "
                    "not %s" % type(start).__name__)


def save_mcap(stub: Any, run_id: str, path: Union[str, "os.PathLike[str]"],
              compression: str = "zstd", start: StartLike = None, probe_set: str = "",
              wait: bool = True) -> "run_pb2.RunInfo":
    """Streams ExportMcap for `run_id` into `path` (written as path + ".tmp" and renamed once
    whole: an error leaves no file). Returns the run's info."""
    if compression not in COMPRESSIONS:
        raise ValueError("compression must be one of %s, not %r"
                         % (", ".join(COMPRESSIONS), compression))
    request = service_pb2.ExportMcapRequest(run_id=run_id, probe_set=probe_set,
                                            compression=compression, start=start_text(start),
                                            wait=wait)
    path = os.fspath(path)
    temporary = path + ".tmp"
    info: Optional[run_pb2.RunInfo] = None
    try:
        with open(temporary, "wb") as out, rpc_errors():
            for chunk in stub.ExportMcap(request):
                if chunk.HasField("info"):
                    info = chunk.info
                out.write(chunk.data)
        os.replace(temporary, path)
    finally:
        if os.path.exists(temporary):
            os.remove(temporary)
    return info if info is not None else run_pb2.RunInfo()
