"""mbstream_client: the Python client of an mbstream simulation server.

    import mbstream_client as mb
    with mb.connect("127.0.0.1:50051") as server:                # checks the server's version
        server.submit("models/irb1600")                          # ModelInfo
        run = server.run("irb1600", "models/irb1600/seed-run.json", duration=2, watch=True)
        for frame in run.watch(progress=True):                   # frames as they arrive
            pass                                                 # frame.t_s (s), frame.q (rad)
        result = run.result(check=True)                          # NumPy arrays, joint names
        result.plot_tcp()

Units are SI everywhere (s, m, rad, N*m, J); positions are in the model's base (world) frame.
The stubs generated from proto/mbstream/v1 are modules of this package (frame_pb2, run_pb2,
run_spec_pb2, model_pb2, replay_pb2, simulation_service_pb2 and their _grpc twins), written at build time
by setup.py. Errors are MbstreamError subclasses named after the gRPC code (BadRequest,
NotFound, Unavailable, ...), each with `.code` (the code's name) and `.message` (the
server's).
"""
from ._stubs import (WIRE_MAJOR, frame_pb2, model_pb2, replay_pb2, run_pb2, run_spec_pb2,
                     simulation_service_pb2, simulation_service_pb2_grpc)
from ._version import __version__
from .bundle import read_model_bundle
from .client import Client, connect
from .compare import Comparison, compare_results
from .control import Contact, ControlLoop, ControlState
from .errors import (AlreadyExists, BadRequest, Cancelled, DeadlineExceeded, FailedPrecondition,
                     IncompatibleServer, MbstreamError, NotFound, OutOfRange, PermissionDenied,
                     ResourceExhausted, RunFailed, ServerError, Unauthenticated, Unavailable,
                     Unimplemented)
from .result import Result
from .run import FINAL_STATES, Frame, ProgressBar, Run, RunInfo
from .server_check import ServerCheck
from .spec import load_spec, spec_to_dict
from .sweep import Sweep
from .sweep_plot import plot_sweep

__all__ = [
    "__version__", "WIRE_MAJOR", "connect", "Client", "Run", "Result", "RunInfo", "Frame",
    "ProgressBar", "ServerCheck", "load_spec", "spec_to_dict", "read_model_bundle",
    "FINAL_STATES", "Comparison", "compare_results", "plot_sweep", "Sweep", "ControlLoop",
    "ControlState", "Contact",
    # errors
    "MbstreamError", "BadRequest", "NotFound", "AlreadyExists", "FailedPrecondition",
    "OutOfRange", "Unauthenticated", "PermissionDenied", "ResourceExhausted", "Unavailable",
    "DeadlineExceeded", "Cancelled", "Unimplemented", "ServerError", "IncompatibleServer",
    "RunFailed",
    # generated messages and stubs
    "frame_pb2", "model_pb2", "replay_pb2", "run_pb2", "run_spec_pb2", "simulation_service_pb2",
    "simulation_service_pb2_grpc",
]
