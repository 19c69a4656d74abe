"""The stubs generated from proto/mbstream/v1 at build time (setup.py puts them in this
package). A clear message when they are missing: the package was not installed."""
try:
    from . import (control_pb2, frame_pb2, model_pb2, replay_pb2, run_pb2, run_spec_pb2,  # noqa: F401
                   simulation_service_pb2, simulation_service_pb2_grpc)
except ImportError as error:  # pragma: no cover - only from a bare source tree
    raise ImportError(
        "mbstream_client: the generated stubs (mbstream_client.*_pb2) are missing: install the "
        "package (pip install --no-build-isolation --no-deps ./client/python, or -e for an "
        "editable install) instead of importing it from the source folder") from error

# The wire's major version: the proto package is mbstream.v<N>.
WIRE_PACKAGE = simulation_service_pb2.DESCRIPTOR.package
WIRE_MAJOR = int(WIRE_PACKAGE.rsplit(".v", 1)[1])
SERVICE_NAME = WIRE_PACKAGE + ".Simulation"
