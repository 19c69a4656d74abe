"""mbstream_client: the Python client of an mbstream simulation server.

    import mbstream_client as mb
    with mb.connect("127.0.0.1:50051") as server:
        model = server.submit("models/irb1600")               # ModelInfo
        run = server.run("irb1600", "models/irb1600/seed-run.json", duration=2, watch=True)
        for frame in run:                                      # frames as they arrive
            print(frame.seq, frame.t_s, frame.tcp_m.x)
        result = run.result()                                  # NumPy arrays + stats dict
        print(result.tcp.shape, result.stats["cpu_s"])

The generated stubs are the package `mbstream.v1` (build output <build>/client/python/gen);
this package is named `mbstream_client` so the two never collide. Errors are
MbstreamError(code, message) with the gRPC status code name.
"""
from ._stubs import frame_pb2, model_pb2, run_pb2, run_spec_pb2, simulation_service_pb2
from .bundle import read_model_bundle
from .client import Client, connect
from .errors import MbstreamError
from .result import Result
from .run import FINAL_STATES, Run
from .spec import load_spec, spec_to_dict

__all__ = ["connect", "Client", "Run", "Result", "MbstreamError", "load_spec", "spec_to_dict",
           "read_model_bundle", "FINAL_STATES", "frame_pb2", "model_pb2", "run_pb2",
           "run_spec_pb2", "simulation_service_pb2"]
