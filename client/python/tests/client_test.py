#!/usr/bin/python3
"""Tests of mbstream_client against a live mbstream-server ($MBSTREAM_SERVER).

ctest runs them through run_with_server.py, which starts a fresh server on port 0 with a
temporary data folder, with the python of the venv tests/make_venv.py made (the installed
package, not this source tree). Run by hand from the repository root, with the package
installed (client/python/README.md):
    MBSTREAM_SERVER=127.0.0.1:PORT venv/bin/python client/python/tests/client_test.py -v
"""
import concurrent.futures
import io
import math
import os
import queue
import shutil
import subprocess
import sys
import tempfile
import unittest
from unittest import mock

import grpc
import numpy as np

import mbstream_client as mb
from mbstream_client import simulation_service_pb2 as service_pb2

SEED_RUN = "models/irb1600/seed-run.json"
SEED_SERVO = "models/irb1600/seed-servo.json"
EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples")


def rot(axis, angle):
    c, s = math.cos(angle), math.sin(angle)
    if axis == "x":
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == "y":
        return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def seed_tcp(q):
    """Closed-form FK of the seed chain: Rz(q1) Tr(0.150,0,0.4865) Ry(q2) Tr(0,0,0.475) Ry(q3)
    Tr(0.600,0,0) Rx(q4) Ry(q5) Rx(q6) Tr(0.065,0,0), m and rad."""
    steps = [("R", "z", q[0]), ("T", (0.150, 0, 0.4865)), ("R", "y", q[1]), ("T", (0, 0, 0.475)),
             ("R", "y", q[2]), ("T", (0.600, 0, 0)), ("R", "x", q[3]), ("R", "y", q[4]),
             ("R", "x", q[5]), ("T", (0.065, 0, 0))]
    rotation, position = np.eye(3), np.zeros(3)
    for step in steps:
        if step[0] == "R":
            rotation = rotation @ rot(step[1], step[2])
        else:
            position = position + rotation @ np.array(step[1], dtype=float)
    return position


def answer_probes(client, start_run, probe="tcp"):
    """A stand-in for a viewer: follows the server's runs, calls start_run() once the
    subscription is registered (so that it sees that run from its first frame: no race with
    the run's start), answers each of the run's frames with a probe at the frame's TCP, and
    half-closes after the run ended (the server then has every report). Returns (the run,
    the reports sent, the frames the server dropped for this subscriber)."""
    replies = queue.Queue()

    def requests():
        start = service_pb2.SubscribeRequest()
        start.start.follow = True
        yield start
        while True:
            reply = replies.get()
            if reply is None:
                return
            yield reply

    run, answered, missed = None, 0, 0
    for event in client.stub.Subscribe(requests()):
        kind = event.WhichOneof("event")
        if kind == "subscribed":
            run = start_run()
        elif kind == "frames" and run is not None and event.frames.run_id == run.id:
            missed += event.frames.missed
            for frame in event.frames.frames:
                reply = service_pb2.SubscribeRequest()
                reply.probe.run_id = run.id
                reply.probe.seq = frame.seq
                reply.probe.t_s = frame.t_s
                reply.probe.probe = probe
                reply.probe.position_m.CopyFrom(frame.tcp_m)
                reply.probe.frame = "World"
                replies.put(reply)
                answered += 1
        elif kind == "run_ended" and run is not None and event.run_ended.id == run.id:
            replies.put(None)  # goodbye: the server ends the stream once it has read it
    return run, answered, missed


class ClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.address = os.environ.get("MBSTREAM_SERVER")
        if not cls.address:
            raise unittest.SkipTest("set MBSTREAM_SERVER (run_with_server.py does)")
        cls.client = mb.connect(cls.address)
        cls.tmp = tempfile.mkdtemp(prefix="mbstream-pytest-")

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def write(self, name, text):
        path = os.path.join(self.tmp, name)
        with open(path, "w") as f:
            f.write(text)
        return path

    def test_submit_same_bundle_twice_gives_the_same_id(self):
        first = self.client.submit("models/irb1600")
        second = self.client.submit("models/irb1600")
        self.assertTrue(first.id.startswith("m-"))
        self.assertEqual(first.id, second.id)
        self.assertEqual(first.dofs, 6)
        self.assertTrue(first.has_scene)
        self.assertIn(first.id, [m.id for m in self.client.models()])
        with open("models/pendulum/double_pendulum.urdf") as f:
            mine = self.write("mine.urdf", f.read() + "<!-- python test -->\n")
        a = self.client.submit(mine, name="mine")
        b = self.client.submit(mine, name="mine")
        self.assertEqual(a.id, b.id)
        self.assertNotEqual(a.id, first.id)
        self.assertEqual(self.client.model("mine").id, a.id)

    def test_bad_urdf_raises_invalid_argument_with_the_importers_message(self):
        bad = self.write("bad.urdf", "<robot name='bad'><link name='a'/>"
                         "<joint name='j' type='revolute'><parent link='a'/>"
                         "<child link='nosuch'/></joint></robot>")
        with self.assertRaises(mb.BadRequest) as caught:
            self.client.submit(bad)
        self.assertEqual(caught.exception.code, "INVALID_ARGUMENT")
        self.assertEqual(caught.exception.status, grpc.StatusCode.INVALID_ARGUMENT)
        self.assertTrue(caught.exception.message)
        self.assertIn(caught.exception.message, str(caught.exception))
        # A local input error has the same shape.
        empty = os.path.join(self.tmp, "empty")
        os.makedirs(empty, exist_ok=True)
        with self.assertRaises(mb.MbstreamError) as caught:
            self.client.submit(empty)
        self.assertEqual(caught.exception.code, "INVALID_ARGUMENT")
        self.assertIn("exactly one .urdf", caught.exception.message)

    def test_repair_true_fixes_a_defect_that_is_an_error_without_it(self):
        # 0.1 + 0.1 < 0.2001: breaks the triangle inequality by 1e-4, as CAD exports do.
        odd = self.write("odd.urdf", """<robot name="odd">
  <link name="base"/>
  <link name="arm"><inertial><mass value="2"/>
    <inertia ixx="0.1" iyy="0.1" izz="0.2001" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="arm"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
""")
        with self.assertRaises(mb.MbstreamError) as caught:
            self.client.submit(odd)
        self.assertEqual(caught.exception.code, "INVALID_ARGUMENT")
        self.assertIn("--repair", caught.exception.message)
        info = self.client.submit(odd, repair=True)
        self.assertEqual(info.dofs, 1)
        self.assertTrue(any("repaired:" in w for w in info.warnings), info.warnings)

    def test_couple_mimic_true_holds_a_mimic_joint_to_its_leader(self):
        rods = self.write("rods.urdf", """<robot name="rods"><link name="base"/>
  <link name="a"><inertial><origin xyz="0 0 -0.3"/><mass value="1"/>
    <inertia ixx="0.03" iyy="0.03" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b"><inertial><origin xyz="0 0 -0.3"/><mass value="1"/>
    <inertia ixx="0.03" iyy="0.03" izz="0.001" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="ja" type="continuous"><parent link="base"/><child link="a"/>
    <axis xyz="0 1 0"/></joint>
  <joint name="jb" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 1 0"/>
    <origin xyz="0 0 -0.1"/><mimic joint="ja" multiplier="2" offset="-0.1"/></joint>
</robot>
""")
        free = self.client.submit(rods)
        self.assertTrue(any("--couple-mimic" in w for w in free.warnings), free.warnings)
        coupled = self.client.submit(rods, couple_mimic=True)
        self.assertNotEqual(coupled.id, free.id)
        self.assertFalse(any("mimic" in w for w in coupled.warnings), coupled.warnings)
        spec = {"duration_s": 0.5, "output_interval_s": 0.05, "formulation": "joint",
                "method": "bdf", "rtol": 1e-9, "atol": 1e-11, "initial_q": [0.5, 0.9]}
        result = self.client.run(coupled.id, spec).result(check=True)
        self.assertEqual(list(result.joint_names), ["ja", "jb"])
        np.testing.assert_allclose(result.q[:, 1], 2.0 * result.q[:, 0] - 0.1, atol=1e-8)
        self.assertGreater(abs(result.q[-1, 0] - 0.5), 0.01)  # it swung

    def test_errors_carry_the_status_name_and_the_servers_message(self):
        with self.assertRaises(mb.NotFound) as caught:
            self.client.run("nosuch")
        self.assertEqual(caught.exception.code, "NOT_FOUND")
        self.assertIn("no model 'nosuch'", caught.exception.message)
        with self.assertRaises(mb.NotFound) as caught:
            self.client.get_run("r-nosuch")
        self.assertEqual(caught.exception.code, "NOT_FOUND")
        with self.assertRaises(mb.BadRequest) as caught:
            self.client.run("irb1600", SEED_RUN, duration=-1)
        self.assertEqual(caught.exception.code, "INVALID_ARGUMENT")
        self.assertIn("duration_s", caught.exception.message)

    def test_seed_run_tcp_matches_closed_form_kinematics(self):
        result = self.client.run("irb1600", SEED_RUN).result(check=True)
        self.assertEqual(result.t.shape, (401,))
        amplitudes = [math.pi, math.pi / 3, math.pi / 4, math.pi, 0.6 * math.pi, math.pi]
        omega = math.pi / 10
        for k, t in enumerate(result.t):
            self.assertAlmostEqual(t, 0.05 * k, delta=1e-12)
            q = [a * math.sin(omega * t) for a in amplitudes]
            np.testing.assert_allclose(result.q[k], q, rtol=0, atol=1e-9)
            np.testing.assert_allclose(result.tcp[k], seed_tcp(q), rtol=0, atol=1e-9)
        self.assertEqual(result.stats["formulation"], "kinematic")

    def test_watch_yields_frames_in_order_as_they_arrive(self):
        run = self.client.run("irb1600", SEED_RUN, duration=2, realtime=8, watch=True)
        frames = list(run)
        self.assertEqual(run.state, "FINISHED")
        self.assertTrue(frames)
        seqs = [f.seq for f in frames]
        self.assertEqual(seqs, sorted(set(seqs)))  # strictly increasing
        self.assertEqual(seqs[-1], 40)
        self.assertLessEqual(len(frames) + run.missed, 41)
        for f in frames:
            self.assertAlmostEqual(f.t_s, 0.05 * f.seq, delta=1e-12)
            self.assertEqual(len(f.q), 6)
        # The frames are the stored result's frames.
        result = run.result()
        for f in frames:
            np.testing.assert_array_equal(result.tcp[f.seq], [f.tcp_m.x, f.tcp_m.y, f.tcp_m.z])

    def test_cancel_stops_a_run_and_keeps_its_partial_result(self):
        run = self.client.run("irb1600", SEED_RUN, realtime=1)  # 20 s of wall time
        with self.assertRaises(mb.FailedPrecondition) as caught:
            run.result(wait=False)  # still running
        self.assertEqual(caught.exception.code, "FAILED_PRECONDITION")
        run.cancel()
        info = run.wait()
        self.assertEqual(mb.run_pb2.RunState.Name(info.state), "CANCELLED")
        result = run.result()
        self.assertEqual(result.state, "CANCELLED")
        self.assertLess(len(result.t), 401)
        with self.assertRaises(mb.RunFailed) as caught:
            run.result(check=True)
        self.assertEqual(caught.exception.code, "CANCELLED")
        self.assertEqual(self.client.get_run(run.id).state, "CANCELLED")

    def test_result_arrays_have_the_documented_shapes(self):
        run = self.client.run("irb1600", SEED_SERVO, duration=1)
        result = run.result(check=True)
        self.assertEqual(result.run_id, run.id)
        self.assertEqual(result.t.shape, (21,))
        self.assertEqual(result.seq.tolist(), list(range(21)))
        for name in ("q", "qd", "tau"):
            self.assertEqual(getattr(result, name).shape, (21, 6), name)
        self.assertEqual(result.tcp.shape, (21, 3))
        self.assertEqual(result.probes.shape, (0,))
        self.assertEqual(len(result.joint_names), 6)
        self.assertEqual(result.stats["state"], "FINISHED")
        self.assertEqual(result.stats["formulation"], "joint")
        self.assertGreater(result.stats["steps"], 0)
        self.assertGreater(result.stats["cpu_s"], 0)
        self.assertTrue(np.all(np.isfinite(result.tau)))
        # A run without torques has an empty tau.
        kinematic = self.client.run("irb1600", SEED_RUN, duration=1).result()
        self.assertEqual(kinematic.tau.shape, (21, 0))
        self.assertIn(run.id, [r.id for r in self.client.runs()])
        self.assertEqual(self.client.runs(limit=1)[0].id, kinematic.run_id)

    def test_keep_stores_every_nth_frame_and_the_summary_covers_them_all(self):
        full = self.client.run("irb1600", SEED_SERVO, duration=1).result(check=True)
        kept = self.client.run("irb1600", SEED_SERVO, duration=1, keep="every:4").result()
        self.assertTrue(kept.finished, kept.message)
        self.assertEqual(kept.seq.tolist(), list(range(6)))  # consecutive: replays need it
        indices = [0, 4, 8, 12, 16, 20]  # 20, the last, is a multiple of 4 already
        self.assertEqual(kept.t.tolist(), full.t[indices].tolist())
        np.testing.assert_array_equal(kept.q, full.q[indices])
        summary = kept.stats["summary"]
        self.assertEqual(summary["keep"], "every:4")
        self.assertEqual((summary["frames_computed"], summary["frames_kept"]), (21, 6))
        np.testing.assert_array_equal(summary["q_final"], full.q[-1])
        self.assertEqual([j["effort_peak"] for j in summary["joints"]],
                         np.abs(full.tau).max(axis=0).tolist())
        nothing = self.client.run("irb1600", SEED_SERVO, duration=1, keep="summary").result()
        self.assertEqual(nothing.t.shape, (0,))
        self.assertEqual(nothing.stats["summary"]["frames_computed"], 21)
        with self.assertRaises(mb.BadRequest) as caught:
            self.client.run("irb1600", SEED_SERVO, keep="every:0")
        self.assertIn("keep", str(caught.exception))

    def test_a_sweep_of_servo_gains_is_one_table_in_point_order(self):
        table = self.client.sweep("irb1600", SEED_SERVO, duration=0.5, window=2,
                                  grid={"drives[1].pd_servo.kp": [100, 400, 1600],
                                        "rtol": [1e-6, 1e-8]})
        self.assertEqual(len(table), 6)
        self.assertEqual(table["drives[1].pd_servo.kp"].tolist(), [100, 100, 400, 400, 1600, 1600])
        self.assertEqual(table["rtol"].tolist(), [1e-6, 1e-8] * 3)
        self.assertEqual(set(table["state"]), {"FINISHED"})
        self.assertEqual(table["frames_kept"].tolist(), [0] * 6)  # the summary only
        errors = table["tracking_error_max:joint2"].tolist()[::2]
        self.assertGreater(errors[0], errors[1])  # a stiffer servo tracks better
        self.assertGreater(errors[1], errors[2])
        rows = self.client.sweep("irb1600", SEED_SERVO, duration=0.5, keep="final",
                                 points=[{"drives[0].pd_servo.kd": 20.0}])
        self.assertEqual(rows["frames_kept"].tolist(), [1])
        self.assertEqual(len(self.client.result(rows["run_id"][0]).t), 1)
        with self.assertRaises(mb.BadRequest) as caught:
            self.client.sweep("irb1600", SEED_SERVO, grid={"drives[9].pd_servo.kp": [1]})
        self.assertIn("drives[9]", str(caught.exception))
        with self.assertRaises(ValueError):
            self.client.sweep("irb1600", SEED_SERVO)

    def test_a_sweep_reports_its_progress_and_is_cancelled_by_its_id(self):
        table = self.client.sweep("irb1600", SEED_SERVO, duration=0.2, progress=True,
                                  grid={"drives[1].pd_servo.kp": [100, 400]})
        sweep_id = table.attrs["sweep_id"]
        self.assertTrue(sweep_id.startswith("s-"), sweep_id)
        self.assertFalse(table.attrs["cancelled"])
        done = self.client.sweep_progress(sweep_id)
        self.assertEqual((done.total_points, done.started_runs, done.ended_runs), (2, 2, 2))
        self.assertEqual(list(done.run_ids), table["run_id"].tolist())
        self.assertIn("2/2 runs ended (FINISHED 2)", mb.sweep.progress_line(done))
        with self.assertRaises(mb.NotFound):
            self.client.sweep_progress("s-nosuch")

        # Paced runs of 20 s (the frames kept are paced), two started at a time of four points: cancelled from another
        # client while the sweep() fills its table, which then ends with the runs it started.
        with concurrent.futures.ThreadPoolExecutor(1) as pool:
            filling = pool.submit(self.client.sweep, "irb1600", SEED_SERVO, duration=20,
                                  realtime=1.0, keep="all",  # paced: its frames are
                                  window=2, grid={"rtol": [1e-6, 1e-7, 1e-8, 1e-9]})
            started = []
            while not started and not filling.done():  # the sweep's first runs, once queued
                started = [r for r in self.client.runs("irb1600", limit=20)
                           if r.sweep_id and r.spec.realtime == 1.0
                           and r.state != mb.run_pb2.CANCELLED]
            self.assertTrue(started, "the sweep ended before any run was seen")
            with mb.connect(self.address) as other:
                cancelled = other.cancel_sweep(started[0].sweep_id)
            self.assertTrue(cancelled.cancelled)
            self.assertEqual(cancelled.ended_runs, cancelled.started_runs)
            table = filling.result(timeout=60)
        self.assertTrue(table.attrs["cancelled"])
        self.assertEqual(set(table["state"]), {"CANCELLED"})
        self.assertLessEqual(len(table), 4)
        self.assertEqual(self.client.sweep_progress(table.attrs["sweep_id"]).total_points, 4)

    def test_a_sweep_started_by_one_client_is_waited_for_by_another(self):
        sweep = self.client.start_sweep("irb1600", SEED_SERVO, duration=0.1, window=2,
                                        grid={"drives[1].pd_servo.kp": [100, 200, 400, 800, 1600]})
        self.assertTrue(sweep.id.startswith("s-"), sweep.id)
        with mb.connect(self.address) as other:  # the server feeds it: anyone may follow it
            table = mb.Sweep(other, sweep.id).wait()
        self.assertEqual(table["drives[1].pd_servo.kp"].tolist(), [100, 200, 400, 800, 1600])
        self.assertEqual(set(table["state"]), {"FINISHED"})
        self.assertEqual(table.attrs["sweep_id"], sweep.id)
        done = sweep.progress()
        self.assertEqual((done.total_points, done.started_runs, done.ended_runs, done.window),
                         (5, 5, 5, 2))
        again = self.client.sweep_handle(sweep.id).wait()  # a finished sweep: its whole table
        self.assertEqual(again["run_id"].tolist(), table["run_id"].tolist())

    def test_run_many_and_results_in_one_call_each(self):
        durations = [0.5, 1.0, 0.25]
        runs = self.client.run_many(
            "irb1600", [mb.load_spec(SEED_SERVO, duration=d) for d in durations])
        self.assertEqual(len(runs), 3)
        self.assertEqual(len({run.id for run in runs}), 3)
        asked = [runs[2], runs[0].id, runs[1]]  # handles or ids, in any order
        results = self.client.results(asked)
        self.assertEqual([r.run_id for r in results], [runs[2].id, runs[0].id, runs[1].id])
        for result, duration in zip(results, [durations[2], durations[0], durations[1]]):
            self.assertTrue(result.finished, result.message)
            self.assertEqual(len(result.t), round(duration / 0.05) + 1)
            self.assertAlmostEqual(result.t[-1], duration)
        self.assertEqual(runs[2].info.state, results[0].info.state)  # handles updated
        with self.assertRaises(mb.BadRequest) as caught:
            self.client.run_many("irb1600", [SEED_SERVO, SEED_SERVO], duration=-1.0)
        self.assertIn("specs[0]", str(caught.exception))  # the first bad one is named

    def test_concurrent_runs_from_threads(self):
        with concurrent.futures.ThreadPoolExecutor(3) as pool:
            results = list(pool.map(
                lambda rtol: self.client.run("irb1600", SEED_SERVO, duration=1,
                                             rtol=rtol).result(check=True),
                [1e-4, 1e-6, 1e-8]))
        self.assertEqual(len({r.run_id for r in results}), 3)
        self.assertEqual([r.info.spec.rtol for r in results], [1e-4, 1e-6, 1e-8])

    def test_probe_reports_come_back_in_the_result_and_tcp_vs_probe_plots_them(self):
        run, answered, missed = answer_probes(
            self.client, lambda: self.client.run("irb1600", SEED_RUN, duration=2, realtime=8))
        result = run.result(check=True)
        self.assertEqual(answered + missed, 41)  # subscribed before the run started
        self.assertGreater(answered, 0)
        self.assertEqual(len(result.probes), answered)
        tcp = result.probe("tcp")
        np.testing.assert_array_equal(tcp["x"], result.tcp[tcp["seq"], 0])
        self.assertTrue(np.all(tcp["latency_us"] >= 0))
        out = os.path.join(self.tmp, "tcp_vs_probe.png")
        done = subprocess.run(
            [sys.executable, os.path.join(EXAMPLES, "tcp_vs_probe.py"), "--server", self.address,
             "--run", run.id, "--out", out], capture_output=True, text=True, timeout=60)
        self.assertEqual(done.returncode, 0, done.stdout + done.stderr)
        self.assertIn("median probe latency", done.stdout)
        self.assertIn("max |probe - TCP| 0", done.stdout)
        self.assertGreater(os.path.getsize(out), 1000)

    def test_connect_checks_the_servers_wire_version(self):
        self.assertIn("mbstream.v1.Simulation", self.client.server.services)
        self.assertEqual(self.client.server.wire_major, mb.WIRE_MAJOR)

    def test_watch_with_events_and_a_progress_bar(self):
        run = self.client.run("irb1600", SEED_RUN, duration=2, realtime=8)
        out = io.StringIO()
        with mock.patch.dict(sys.modules, {"tqdm": None}):  # the plain-text bar
            bar = mb.ProgressBar(run.id, stream=out)
        items = list(run.watch(progress=bar, events=True, progress_interval_s=0.05))
        infos = [i for i in items if isinstance(i, mb.RunInfo)]
        frames = [i for i in items if isinstance(i, mb.Frame)]
        self.assertTrue(frames)
        self.assertTrue(infos)
        self.assertEqual(mb.run_pb2.RunState.Name(infos[-1].state), "FINISHED")
        self.assertAlmostEqual(infos[-1].t_s, 2.0, delta=1e-9)
        self.assertEqual(frames[-1].seq, 40)
        lines = out.getvalue().splitlines()
        self.assertTrue(lines[-1].endswith("2.00/2.00 s simulated, 41 frames, FINISHED"), lines)
        self.assertTrue(bar.closed)

    def test_wait_with_a_progress_bar(self):
        run = self.client.run("irb1600", SEED_RUN, duration=1, realtime=8)
        out = io.StringIO()
        with mock.patch.dict(sys.modules, {"tqdm": None}), mock.patch("sys.stderr", out):
            info = run.wait(progress=True)
        self.assertEqual(mb.run_pb2.RunState.Name(info.state), "FINISHED")
        lines = out.getvalue().splitlines()
        self.assertTrue(lines, "no progress lines")
        self.assertTrue(lines[-1].startswith(run.id + ": 100.0% 1.00/1.00 s simulated"), lines)

    def test_an_sdf_linkage_is_submitted_and_its_cut_joint_is_in_the_result(self):
        info = self.client.submit("models/linkages/four_bar.sdf", name="four_bar_py")
        self.assertEqual(info.dofs, 3)  # the spanning tree's joints
        # The same bundle as the built-in four_bar: the same model (its id), whatever the name.
        result = self.client.run(info.id, "models/linkages/four_bar-passive.json",
                                 duration=0.5).result(check=True)
        self.assertEqual(result.joint_names,
                         ["crank_joint", "rocker_joint", "coupler_joint", "loop_joint"])
        self.assertEqual(result.q.shape[1], 4)
        # Every axis is -y: crank + coupler + loop_joint - rocker stays 0 (the loop closes).
        q = result.q
        closure = q[:, 0] + q[:, 2] + q[:, 3] - q[:, 1]
        self.assertLess(float(np.max(np.abs(closure))), 1e-8)
        self.assertGreater(float(np.max(np.abs(q[:, 3]))), 0.01)  # the cut joint turned
        self.assertEqual(list(result.info.stats.loops.cut_joints), ["loop_joint (revolute)"])

    def test_a_world_folder_is_submitted_with_its_included_models(self):
        # issue 43: the client writes the includes into the world; three boxes move freely.
        info = self.client.submit("models/worlds/irb1600_table", name="world_py")
        self.assertEqual(info.name, "world_py")
        self.assertEqual(info.dofs, 6 + 3 * 6)
        self.assertEqual(info.positions, 6 + 3 * 7)
        self.assertEqual(list(info.position_names[6:13]),
                         ["box_a::link." + c for c in ("x", "y", "z", "qw", "qx", "qy", "qz")])
        self.assertEqual(info.tcp_frame, "irb1600::tcp")

    def test_result_carries_the_models_joint_names(self):
        result = self.client.run("irb1600", SEED_SERVO, duration=1).result(check=True)
        model = self.client.model("irb1600")
        self.assertEqual(result.joint_names, [j.name for j in model.joints])
        self.assertEqual(len(result.joint_names), 6)
        self.assertEqual(result.server_version, mb.__version__)  # the same checkout
        first = result.joint_names[0]
        np.testing.assert_array_equal(result.q[:, result.joint(first)], result.q[:, 0])
        try:
            import pandas  # noqa: F401
        except ImportError:
            return
        table = result.to_pandas("tau")
        self.assertEqual(list(table.columns), result.joint_names)
        np.testing.assert_array_equal(table.values, result.tau)


class SpecTest(unittest.TestCase):
    def test_spec_from_path_dict_and_overrides(self):
        spec = mb.load_spec(SEED_RUN, duration=2, rtol=1e-9, method="adams", realtime=0)
        self.assertEqual(spec.duration_s, 2)
        self.assertEqual(spec.rtol, 1e-9)
        self.assertEqual(spec.method, "adams")
        self.assertEqual(len(spec.drives), 6)
        self.assertTrue(spec.HasField("output_interval_s"))
        spec = mb.load_spec({"durationS": 3, "initial_q": [1, 2]}, initial_q=[0.5], step=0.01,
                            gravity={"z": -1.0})
        self.assertEqual(spec.duration_s, 3)
        self.assertEqual(list(spec.initial_q), [0.5])  # replaced, not extended
        self.assertEqual(spec.fixed_step_s, 0.01)
        self.assertEqual(spec.gravity.z, -1.0)
        self.assertFalse(mb.load_spec().HasField("duration_s"))  # absent: server defaults
        with self.assertRaises(TypeError):
            mb.load_spec(None, nosuch=1)
        with self.assertRaises(mb.BadRequest) as caught:
            mb.load_spec({"duration_s": "soon"})
        self.assertEqual(caught.exception.code, "INVALID_ARGUMENT")


if __name__ == "__main__":
    unittest.main()
