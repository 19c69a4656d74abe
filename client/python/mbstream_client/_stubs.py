"""Finds and imports the stubs generated from proto/ (package `mbstream.v1`).

The build writes them to <build>/client/python/gen/mbstream/v1/. They are found, in order:
on sys.path (PYTHONPATH=client/python:<build>/client/python/gen, as ctest sets it); in the
folder named by MBSTREAM_PYTHON_GEN; in the newest <repo>/build*/client/python/gen.
"""
import glob
import importlib
import os
import sys

_HERE = os.path.dirname(os.path.abspath(__file__))
_REPO = os.path.normpath(os.path.join(_HERE, "..", "..", ".."))


def _candidates():
    env = os.environ.get("MBSTREAM_PYTHON_GEN")
    if env:
        yield env
    found = glob.glob(os.path.join(_REPO, "build*", "client", "python", "gen"))
    for path in sorted(found, key=os.path.getmtime, reverse=True):
        yield path


def _import_generated():
    names = ("model_pb2", "frame_pb2", "run_spec_pb2", "run_pb2", "simulation_service_pb2",
             "simulation_service_pb2_grpc")
    try:
        return [importlib.import_module("mbstream.v1." + n) for n in names]
    except ImportError:
        pass
    for path in _candidates():
        if os.path.isfile(os.path.join(path, "mbstream", "v1", "simulation_service_pb2.py")):
            sys.path.insert(0, path)
            for cached in [m for m in sys.modules if m == "mbstream" or m.startswith("mbstream.")]:
                del sys.modules[cached]
            return [importlib.import_module("mbstream.v1." + n) for n in names]
    raise ImportError(
        "mbstream_client: the generated stubs (mbstream.v1.*_pb2) are not found; build the "
        "project (target mbstream_python) and put <build>/client/python/gen on PYTHONPATH "
        "or set MBSTREAM_PYTHON_GEN to it")


(model_pb2, frame_pb2, run_spec_pb2, run_pb2, simulation_service_pb2,
 simulation_service_pb2_grpc) = _import_generated()
