#!/usr/bin/python3
"""Tests of mbstream_client that need no mbstream-server: the installed package's files, the
exception for every gRPC code, the wire-version check at connect, the progress bar, and
Result's names, pandas view and plots. In-process gRPC servers (grpcio) stand in for the
server where a call is needed.

ctest runs it with the python of the venv that tests/make_venv.py made.
"""
import concurrent.futures
import io
import os
import re
import socket
import sys
import tempfile
import unittest
from unittest import mock

import grpc
import numpy as np

import mbstream_client as mb
from mbstream_client import server_check
from mbstream_client import simulation_service_pb2 as service_pb2
from mbstream_client import simulation_service_pb2_grpc as service_grpc
from mbstream_client.result import result_from_chunks

REPO = os.environ.get("MBSTREAM_SOURCE_DIR") or os.path.normpath(
    os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", ".."))


class _AbortingSimulation(service_grpc.SimulationServicer):
    """GetModel(model=CODE_NAME) aborts with that status code and a message naming it."""

    def GetModel(self, request, context):
        context.abort(grpc.StatusCode[request.model], "stand-in says %s" % request.model)


def _reflection_handler(services):
    """A generic handler that answers ServerReflectionInfo's list_services with `services`."""
    def info(requests, context):
        for _ in requests:
            yield server_check.encode_list_services_response(services)

    return grpc.method_handlers_generic_handler(
        "grpc.reflection.v1alpha.ServerReflection",
        {"ServerReflectionInfo": grpc.stream_stream_rpc_method_handler(info)})


class StandIn:
    """An in-process gRPC server on a loopback port: a Simulation servicer and, when
    `services` is given, reflection that names them."""

    def __init__(self, servicer=None, services=None):
        self.server = grpc.server(concurrent.futures.ThreadPoolExecutor(2))
        if servicer is not None:
            service_grpc.add_SimulationServicer_to_server(servicer, self.server)
        if services is not None:
            self.server.add_generic_rpc_handlers((_reflection_handler(services),))
        self.address = "127.0.0.1:%d" % self.server.add_insecure_port("127.0.0.1:0")

    def __enter__(self):
        self.server.start()
        return self

    def __exit__(self, *exc):
        self.server.stop(None)


class PackageTest(unittest.TestCase):
    def test_version_is_the_projects(self):
        with open(os.path.join(REPO, "CMakeLists.txt")) as f:
            version = re.search(r"project\(\s*mbstream\s+VERSION\s+([0-9.]+)", f.read()).group(1)
        self.assertEqual(mb.__version__, version)
        self.assertEqual(mb.WIRE_MAJOR, 1)

    def test_installed_copy_with_its_stubs_and_py_typed(self):
        here = os.path.dirname(mb.__file__)
        self.assertNotEqual(os.path.realpath(os.path.join(REPO, "client", "python",
                                                          "mbstream_client")),
                            os.path.realpath(here), "tests must run against an installed copy")
        for name in ("py.typed", "simulation_service_pb2.py", "simulation_service_pb2_grpc.py",
                     "run_spec_pb2.py", "_version.py"):
            self.assertTrue(os.path.isfile(os.path.join(here, name)), name)
        # The generated modules import each other inside the package: no top-level mbstream.
        self.assertNotIn("mbstream", sys.modules)
        self.assertEqual(mb.run_spec_pb2.RunSpec.__module__, "mbstream_client.run_spec_pb2")

    def test_public_api_has_type_hints_and_docstrings(self):
        for function in (mb.connect, mb.Client.run, mb.Client.sweep, mb.Client.submit, mb.Run.watch,
                         mb.Run.result, mb.Result.to_pandas, mb.Result.plot_tcp,
                         mb.Result.plot_joints, mb.load_spec, mb.read_model_bundle,
                         mb.plot_sweep, mb.Client.sweep_progress, mb.Client.cancel_sweep):
            self.assertIn("return", function.__annotations__, function.__qualname__)
            self.assertTrue(function.__doc__, function.__qualname__)
        self.assertIn("base (world) frame", mb.Result.__doc__)


class ErrorTest(unittest.TestCase):
    """Every gRPC status code a call can fail with raises its own exception class, with the
    server's message and the code's name."""

    EXPECTED = {
        "INVALID_ARGUMENT": mb.BadRequest, "NOT_FOUND": mb.NotFound,
        "ALREADY_EXISTS": mb.AlreadyExists, "FAILED_PRECONDITION": mb.FailedPrecondition,
        "OUT_OF_RANGE": mb.OutOfRange, "UNAUTHENTICATED": mb.Unauthenticated,
        "PERMISSION_DENIED": mb.PermissionDenied, "RESOURCE_EXHAUSTED": mb.ResourceExhausted,
        "UNAVAILABLE": mb.Unavailable, "DEADLINE_EXCEEDED": mb.DeadlineExceeded,
        "CANCELLED": mb.Cancelled, "UNIMPLEMENTED": mb.Unimplemented,
        "INTERNAL": mb.ServerError, "UNKNOWN": mb.ServerError, "DATA_LOSS": mb.ServerError,
        "ABORTED": mb.ServerError,
    }

    def test_each_code_raises_its_class_with_the_servers_message(self):
        with StandIn(_AbortingSimulation()) as server, \
                mb.connect(server.address, check=False) as client:
            for code, cls in self.EXPECTED.items():
                with self.subTest(code=code):
                    with self.assertRaises(cls) as caught:
                        client.model(code)
                    error = caught.exception
                    self.assertIsInstance(error, mb.MbstreamError)
                    self.assertEqual(error.code, code)
                    self.assertEqual(error.status, grpc.StatusCode[code])
                    self.assertEqual(error.message, "stand-in says %s" % code)
                    self.assertEqual(str(error), "%s: stand-in says %s" % (code, code))
        self.assertEqual(set(self.EXPECTED), {c.name for c in grpc.StatusCode} - {"OK"})

    def test_local_input_errors_are_bad_requests(self):
        with self.assertRaises(mb.BadRequest) as caught:
            mb.load_spec({"duration_s": "soon"})
        self.assertEqual(caught.exception.code, "INVALID_ARGUMENT")
        with self.assertRaises(mb.BadRequest):
            mb.read_model_bundle("/nonexistent/robot.urdf")
        with self.assertRaises(mb.BadRequest) as caught:
            mb.connect("192.0.2.1:50051", token="s3cret")
        self.assertIn("refusing to send a token in the clear", caught.exception.message)

    def test_a_folder_bundle_carries_a_meshs_material_and_texture(self):
        # issue 30: a textured OBJ keeps its .mtl and image (named beside the mesh); files no
        # mesh names stay home.
        with tempfile.TemporaryDirectory() as tmp:
            files = {"r.urdf": '<robot name="r"/>', "meshes/cube.obj": "mtllib cube.mtl\n",
                     "meshes/cube.mtl": "newmtl a\nmap_Kd -s 1 1 1 ../textures/skin.png\n",
                     "textures/skin.png": "skin", "notes.png": "not named"}
            for name, text in files.items():
                os.makedirs(os.path.dirname(os.path.join(tmp, name)), exist_ok=True)
                with open(os.path.join(tmp, name), "w") as f:
                    f.write(text)
            bundle = mb.read_model_bundle(tmp)
            self.assertEqual([a.name for a in bundle.assets],
                             ["meshes/cube.obj", "meshes/cube.mtl", "textures/skin.png"])

    def test_a_worlds_folder_is_sent_with_its_included_models_written_into_it(self):
        # issue 43: the server reads no file a model names; the client reads the includes.
        world = os.path.join(REPO, "models", "worlds", "irb1600_table")
        bundle = mb.read_model_bundle(world)
        self.assertTrue(bundle.urdf_file_name.endswith("world.sdf"))
        self.assertNotIn("<include", bundle.urdf)
        names = re.findall(r'<model name="([^"]+)"', bundle.urdf)
        self.assertEqual(names, ["irb1600", "table", "box_a", "box_b", "box_c"])
        self.assertIn("<pose>1.1 0.1 1.0 0 0 0.5</pose>", bundle.urdf)
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "w.sdf")
            with open(path, "w") as f:
                f.write('<sdf version="1.8"><world name="w">\n'
                        '<include><uri>model://nowhere</uri></include></world></sdf>\n')
            with self.assertRaises(mb.BadRequest) as caught:
                mb.read_model_bundle(path)
            self.assertIn(path + ":2: <include> of 'model://nowhere': not found; tried " +
                          os.path.join(tmp, "nowhere", "model.config"), caught.exception.message)

    def test_hostile_inputs_are_named_before_any_call(self):
        # issue 36: a URDF that is not UTF-8 is named by file and line, not UnicodeDecodeError.
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "latin1.urdf")
            with open(path, "wb") as f:
                f.write(b'<robot name="r">\n<joint name="j\xff"/>\n</robot>\n')
            with self.assertRaises(mb.BadRequest) as caught:
                mb.read_model_bundle(path)
            self.assertIn("latin1.urdf: line 2: byte 0xFF is not UTF-8", caught.exception.message)
            utf16 = os.path.join(tmp, "utf16.urdf")
            with open(utf16, "wb") as f:
                f.write('<robot name="r"/>'.encode("utf-16"))
            with self.assertRaises(mb.BadRequest) as caught:
                mb.read_model_bundle(utf16)
            self.assertIn("UTF-16", caught.exception.message)
        # A number field's override must be a number: duration="5" is not read as 5.
        with self.assertRaises(TypeError) as caught:
            mb.load_spec(None, duration="5")
        self.assertIn("duration_s must be a number, not str", str(caught.exception))
        with self.assertRaises(TypeError):
            mb.load_spec(None, want_torques=1)
        self.assertEqual(mb.load_spec(None, duration=5).duration_s, 5.0)
        # The model of a run is a str: run(42) and run(None) never reach protobuf.
        client = mb.Client.__new__(mb.Client)
        for model, error in ((42, TypeError), (None, TypeError), ("", ValueError)):
            with self.subTest(model=model):
                with self.assertRaises(error) as caught:
                    client.run(model)
                self.assertIn("model", str(caught.exception))


class ConnectTest(unittest.TestCase):
    def test_nothing_listening_raises_unavailable_at_connect(self):
        # A bound socket that does not listen: connecting is refused, and the port stays ours.
        with socket.socket() as bound:
            bound.bind(("127.0.0.1", 0))
            address = "127.0.0.1:%d" % bound.getsockname()[1]
            with self.assertRaises(mb.Unavailable) as caught:
                mb.connect(address, timeout_s=5)
        self.assertIn("no mbstream server answers at %s" % address, caught.exception.message)
        self.assertIn("start one (mbstream-server --listen", caught.exception.message)

    def test_a_server_of_another_wire_major_version_is_refused_with_a_clear_message(self):
        with StandIn(services=["mbstream.v2.Simulation", "grpc.health.v1.Health"]) as server:
            with self.assertRaises(mb.IncompatibleServer) as caught:
                mb.connect(server.address)
        message = caught.exception.message
        self.assertIn("speaks the mbstream wire protocol v2", message)
        self.assertIn("mbstream_client %s speaks v1" % mb.__version__, message)

    def test_a_server_that_is_not_mbstream_is_refused(self):
        with StandIn(services=["grpc.health.v1.Health"]) as server:
            with self.assertRaises(mb.IncompatibleServer) as caught:
                mb.connect(server.address)
        self.assertIn("is not an mbstream server", caught.exception.message)

    def test_a_v1_server_is_accepted_and_one_without_reflection_too(self):
        with StandIn(service_grpc.SimulationServicer(),
                     services=["mbstream.v1.Simulation"]) as server:
            with mb.connect(server.address) as client:
                self.assertEqual(client.server.wire_major, 1)
                self.assertEqual(client.server.services, ["mbstream.v1.Simulation"])
        with StandIn(service_grpc.SimulationServicer()) as server:
            with mb.connect(server.address) as client:
                self.assertIsNone(client.server.services)  # cannot tell: let it through

    def test_token_is_sent_as_bearer_metadata_on_every_call(self):
        seen = []

        class Recording(service_grpc.SimulationServicer):
            def ListModels(self, request, context):
                seen.append(dict(context.invocation_metadata()).get("authorization"))
                return service_pb2.ListModelsResponse()

            def WatchRun(self, request, context):
                seen.append(dict(context.invocation_metadata()).get("authorization"))
                return iter(())

        with StandIn(Recording(), services=["mbstream.v1.Simulation"]) as server:
            with mb.connect(server.address, token="s3cret") as client:
                self.assertEqual(client.models(), [])
                self.assertEqual(list(client.stub.WatchRun(
                    service_pb2.WatchRunRequest(run_id="r-x"))), [])
            with mb.connect(server.address) as client:
                client.models()
        self.assertEqual(seen, ["Bearer s3cret", "Bearer s3cret", None])


def _info(t_s, state="RUNNING", duration_s=2.0, frames=0):
    return mb.RunInfo(id="r-1", t_s=t_s, duration_s=duration_s, frames=frames,
                      state=mb.run_pb2.RunState.Value(state))


class ProgressTest(unittest.TestCase):
    def test_plain_text_when_tqdm_is_absent(self):
        out = io.StringIO()
        with mock.patch.dict(sys.modules, {"tqdm": None}):  # `import tqdm` fails
            bar = mb.ProgressBar("r-1", stream=out)
        for k in range(21):
            bar.update(_info(0.1 * k, frames=k))
        bar.update(_info(2.0, "FINISHED", frames=21))
        lines = out.getvalue().splitlines()
        self.assertEqual(len(lines), 12, lines)  # 0%, each tenth, and the final state
        self.assertEqual(lines[0], "r-1:   0.0% 0.00/2.00 s simulated, 0 frames, RUNNING")
        self.assertEqual(lines[-1], "r-1: 100.0% 2.00/2.00 s simulated, 21 frames, FINISHED")
        self.assertTrue(bar.closed)

    def test_tqdm_bar_when_installed(self):
        try:
            import tqdm  # noqa: F401
        except ImportError:
            self.skipTest("tqdm is not installed (python3-tqdm)")
        out = io.StringIO()
        bar = mb.ProgressBar("r-1", stream=out)
        bar.update(_info(1.0, frames=10))
        bar.update(_info(2.0, "FINISHED", frames=21))
        text = out.getvalue()
        self.assertIn("100%", text)
        self.assertIn("2.00/2.00 s simulated", text)
        self.assertIn("FINISHED, 21 frames", text)


def _synthetic_result():
    chunk = mb.run_pb2.ResultChunk()
    chunk.info.id = "r-synthetic"
    chunk.info.model_name = "two"
    chunk.info.num_dofs = 2
    chunk.info.joint_names.extend(["shoulder", "elbow"])
    chunk.info.state = mb.run_pb2.FINISHED
    for k in range(5):
        frame = chunk.frames.add(seq=k, t_s=0.1 * k, q=[k, -k], qd=[1, -1], tau=[2 * k, 3])
        frame.tcp_m.x, frame.tcp_m.y, frame.tcp_m.z = k, 0.5, 1.0
    return result_from_chunks([chunk])


def _loop_result(report_loop_forces):
    """Two joints, one cut joint; Frame.tau: the efforts, then its 6 reactions when reported."""
    chunk = mb.run_pb2.ResultChunk()
    chunk.info.num_dofs = 2
    chunk.info.joint_names.extend(["crank", "loop"])
    chunk.info.spec.report_loop_forces = report_loop_forces
    chunk.info.stats.loops.cut_joints.append("loop (revolute)")
    for k in range(3):
        reactions = [10 * k + i for i in range(6)] if report_loop_forces else []
        chunk.frames.add(seq=k, t_s=0.1 * k, q=[k, -k], qd=[1, -1], tau=[2 * k, 3] + reactions)
    return result_from_chunks([chunk])


class ResultTest(unittest.TestCase):
    def test_loop_forces_follow_the_efforts_in_frame_tau(self):
        result = _loop_result(True)
        np.testing.assert_array_equal(result.tau, [[0, 3], [2, 3], [4, 3]])
        self.assertEqual(result.loop_force_names, ["loop"])
        self.assertEqual(result.loop_forces.shape, (3, 6))
        np.testing.assert_array_equal(result.loop_forces[2], [20, 21, 22, 23, 24, 25])
        plain = _loop_result(False)
        np.testing.assert_array_equal(plain.tau, result.tau)
        self.assertEqual(plain.loop_forces.shape, (3, 0))

    def test_joint_names_and_arrays(self):
        result = _synthetic_result()
        self.assertEqual(result.joint_names, ["shoulder", "elbow"])
        self.assertEqual(result.q.shape, (5, 2))
        self.assertEqual(result.joint("elbow"), 1)
        np.testing.assert_array_equal(result.q[:, result.joint("elbow")], [0, -1, -2, -3, -4])
        with self.assertRaises(KeyError) as caught:
            result.joint("wrist")
        self.assertIn("shoulder, elbow", str(caught.exception))

    def test_to_pandas_names_columns_by_joint(self):
        try:
            import pandas  # noqa: F401
        except ImportError:
            self.skipTest("pandas is not installed (python3-pandas)")
        result = _synthetic_result()
        q = result.to_pandas("q")
        self.assertEqual(list(q.columns), ["shoulder", "elbow"])
        self.assertEqual(q.index.name, "t")
        np.testing.assert_allclose(q.index.values, result.t)
        np.testing.assert_array_equal(q["elbow"].values, result.q[:, 1])
        self.assertEqual(list(result.to_pandas("tcp").columns), ["x", "y", "z"])
        everything = result.to_pandas()
        np.testing.assert_array_equal(everything["tau"]["shoulder"].values, result.tau[:, 0])
        self.assertEqual(set(everything.columns.get_level_values(0)),
                         {"q", "qd", "tau", "tcp", "energy"})
        with self.assertRaises(ValueError):
            result.to_pandas("nosuch")

    def test_to_pandas_without_pandas_says_what_to_install(self):
        with mock.patch.dict(sys.modules, {"pandas": None}):
            with self.assertRaises(ImportError) as caught:
                _synthetic_result().to_pandas()
        self.assertIn("python3-pandas", str(caught.exception))

    def test_plots_label_joints_and_units(self):
        import matplotlib
        matplotlib.use("Agg")
        result = _synthetic_result()
        ax = result.plot_joints("tau")
        self.assertEqual([line.get_label() for line in ax.get_lines()], ["shoulder", "elbow"])
        self.assertEqual(ax.get_ylabel(), "tau (N*m | N)")
        ax = result.plot_joints("q", joints=["elbow"])
        np.testing.assert_array_equal(ax.get_lines()[0].get_ydata(), result.q[:, 1])
        ax = result.plot_tcp()
        self.assertEqual(len(ax.get_lines()), 3)
        self.assertIn("base frame", ax.get_ylabel())
        with tempfile.TemporaryDirectory() as tmp:
            ax.figure.savefig(os.path.join(tmp, "tcp.png"))
            self.assertGreater(os.path.getsize(os.path.join(tmp, "tcp.png")), 1000)


class SweepPlotTest(unittest.TestCase):
    """plot_sweep: a metric of a two-axis sweep's table as a heat map, axes in ascending order,
    the mean of repeated points, a missing or unfinished point blank."""

    def test_a_heat_map_of_two_swept_paths(self):
        try:
            import pandas as pd
        except ImportError:
            self.skipTest("pandas is not installed (python3-pandas)")
        import matplotlib
        matplotlib.use("Agg")
        kp, kd, error = "drives[1].pd_servo.kp", "drives[1].pd_servo.kd", "tracking_error_max:j2"
        table = pd.DataFrame({kp: [400, 100, 100, 400, 100, 400],
                              kd: [20.0, 20.0, 40.0, 40.0, 20.0, 80.0],
                              error: [0.1, 0.5, 0.4, 0.05, 0.7, None]})
        table.attrs["sweep_id"] = "s-test"
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, "sweep.png")
            ax = mb.plot_sweep(table, kp, kd, error, path=path)
            self.assertGreater(os.path.getsize(path), 1000)
        grid = ax.images[0].get_array()
        self.assertEqual(grid.shape, (3, 2))  # rows: kd 20, 40, 80; columns: kp 100, 400
        self.assertAlmostEqual(grid[0, 0], 0.6)  # kp 100, kd 20: the mean of two runs
        self.assertAlmostEqual(grid[1, 1], 0.05)
        self.assertTrue(grid.mask[2, 0] and grid.mask[2, 1])  # kd 80: none, and no figure
        self.assertEqual([t.get_text() for t in ax.get_xticklabels()], ["100", "400"])
        self.assertEqual([t.get_text() for t in ax.get_yticklabels()], ["20", "40", "80"])
        self.assertEqual((ax.get_xlabel(), ax.get_ylabel()), (kp, kd))
        self.assertIn("s-test", ax.get_title())
        self.assertEqual(len(ax.texts), 4)  # one per cell with a figure
        with self.assertRaises(ValueError) as caught:
            mb.plot_sweep(table, kp, "rtol", error)
        self.assertIn("rtol", str(caught.exception))


if __name__ == "__main__":
    unittest.main()
