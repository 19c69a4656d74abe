#!/usr/bin/env python3
"""Client.control against a real mbstream-server (run_with_server.py): an external PD equals
the built-in sampled pd_servo to 1e-12, a controller asleep past control_timeout_s fails the
run with the message, a killed controller cancels the run and the server goes on, a NaN
command is refused. Every wait is for an event (a state, the run's end), never for time."""
import math
import os
import signal
import subprocess
import sys
import time
import unittest

import numpy as np

import mbstream_client as mb
from mbstream_client import run_pb2
from server_case import ServerTestCase

SEED_SERVO = os.path.join("models", "irb1600", "seed-servo.json")
H = 1e-4  # s: the seed servo's wrist needs h < 2 I / kd, about 2e-4 s


def sampled_servo():
    spec = mb.load_spec(SEED_SERVO, duration=0.05, output_interval=0.01)
    for drive in spec.drives:
        drive.pd_servo.period_s = H
    return spec


def external(spec, timeout_s=None):
    copy = mb.load_spec(spec)
    del copy.drives[:]
    for drive in spec.drives:
        added = copy.drives.add()
        added.joint = drive.joint
        added.external.period_s = H
    if timeout_s is not None:
        copy.control_timeout_s = timeout_s
    return copy


def seed_law(spec, state, by_name=False):
    """The seed servo's law, term by term as the server sums it; by_name: each joint's q and
    qd read by its name (state["joint1"], state.velocity("joint1")), else by index."""
    effort = []
    for i, drive in enumerate(spec.drives):
        q = state[drive.joint] if by_name else state.q[i]
        qd = state.velocity(drive.joint) if by_name else state.qd[i]
        sines = drive.pd_servo.trajectory.sum_of_sines
        value, rate = sines.offset, 0.0
        for term in sines.terms:
            arg = term.omega * state.t + term.phase
            value += term.amplitude * math.sin(arg)
            rate += (term.amplitude * term.omega) * math.cos(arg)
        effort.append(drive.pd_servo.kp * (value - q) + drive.pd_servo.kd * (rate - qd))
    return effort


class ControlTest(ServerTestCase):
    def test_external_pd_equals_the_built_in_sampled_servo(self):
        servo = sampled_servo()
        builtin = self.client.run("irb1600", servo).result(check=True)
        with self.client.control("irb1600", external(servo)) as loop:
            self.assertEqual(loop.external_joints, ["joint%d" % i for i in range(1, 7)])
            steps = 0
            for state in loop:
                self.assertEqual(state.step, steps)
                loop.send(effort=np.array(seed_law(servo, state)))
                steps += 1
        self.assertEqual(steps, 500)
        self.assertEqual(loop.info.state, run_pb2.FINISHED, loop.info.message)
        self.assertAlmostEqual(loop.final.t, 0.05, places=12)
        controlled = self.client.result(loop.run_id, check=True)
        self.assertEqual(controlled.q.shape, builtin.q.shape)
        self.assertLessEqual(np.max(np.abs(controlled.q - builtin.q)), 1e-12)
        self.assertLessEqual(np.max(np.abs(controlled.qd - builtin.qd)), 1e-12)
        self.assertIn(loop.run_id, [run.id for run in self.client.runs("irb1600")])

    def test_an_arm_among_free_boxes_is_controlled_by_its_coordinates_names(self):
        # The IRB 1600 of a world with three free boxes falling beside it (docs/worlds.md):
        # q has the arm's 6 positions and each box's 7, qd the arm's 6 velocities and each
        # box's 6; the controller reads them by name.
        self.client.submit(os.path.join("models", "worlds", "irb1600_table"), name="table_world")
        joints = ["irb1600::joint%d" % i for i in range(1, 7)]
        servo = sampled_servo()
        for joint, drive in zip(joints, servo.drives):
            drive.joint = joint
        del servo.initial_q[:]  # the world's poses: the arm's zero, the boxes' <pose>s
        del servo.initial_qd[:]
        builtin = self.client.run("table_world", servo).result(check=True)
        with self.client.control("table_world", external(servo)) as loop:
            boxes = [n[:-3] for n in loop.position_names if n.endswith(".qw")]
            self.assertEqual(len(boxes), 3, loop.position_names)
            self.assertEqual((len(loop.position_names), len(loop.velocity_names)), (27, 24))
            for box in boxes:
                at = loop.position_names.index(box + ".x")
                self.assertEqual(loop.position_names[at:at + 7],
                                 [box + s for s in (".x", ".y", ".z", ".qw", ".qx", ".qy", ".qz")])
                at = loop.velocity_names.index(box + ".vx")
                self.assertEqual(loop.velocity_names[at:at + 6],
                                 [box + s for s in (".vx", ".vy", ".vz", ".wx", ".wy", ".wz")])
            self.assertEqual(loop.joint_names, loop.velocity_names)
            self.assertEqual(loop.external_joints, joints)
            steps = 0
            for state in loop:
                self.assertEqual((len(state.q), len(state.qd)), (27, 24))
                for box in boxes:
                    quat = [state[box + s] for s in (".qw", ".qx", ".qy", ".qz")]
                    self.assertAlmostEqual(float(np.linalg.norm(quat)), 1.0, places=14)
                loop.send(effort=np.array(seed_law(servo, state, by_name=True)))
                steps += 1
            with self.assertRaises(mb.BadRequest):
                state["irb1600::joint7"]
        self.assertEqual(steps, 500)
        self.assertEqual(loop.info.state, run_pb2.FINISHED, loop.info.message)
        controlled = self.client.result(loop.run_id, check=True)
        self.assertEqual(controlled.q.shape, builtin.q.shape)
        self.assertLessEqual(np.max(np.abs(controlled.q - builtin.q)), 1e-12)
        self.assertLessEqual(np.max(np.abs(controlled.qd - builtin.qd)), 1e-12)
        self.assertEqual(builtin.position_names, loop.position_names)
        self.assertEqual(builtin.joint_names, loop.velocity_names)
        z = builtin.position(boxes[0] + ".z")
        self.assertLess(builtin.q[-1, z], builtin.q[0, z] - 0.01)  # the box fell
        self.assertEqual(list(builtin.to_pandas("q").columns), loop.position_names)

    def test_states_carry_the_sensor_points(self):
        spec = external(sampled_servo())
        spec.duration_s = 0.002
        spec.output_interval_s = 0.002
        point = spec.sensor_points.add(name="tip", link="link6")
        point.offset_m.x = 0.1
        spec.sensor_points.add(link="link1")
        with self.client.control("irb1600", spec) as loop:
            self.assertEqual(loop.sensor_names, ["tip", "link1"])
            states = 0
            for state in loop:
                self.assertEqual(state.sensors.shape, (2, 3))
                self.assertEqual(state.contacts, [])
                np.testing.assert_array_equal(state.sensor("tip"), state.sensors[0])
                self.assertTrue(np.all(np.isfinite(state.sensors)))
                loop.send(effort=np.zeros(6))
                states += 1
        self.assertEqual(states, 20)
        self.assertEqual(loop.info.state, run_pb2.FINISHED, loop.info.message)
        with self.assertRaises(mb.BadRequest):
            loop.final.sensor("nothing")
        spec.sensor_points[1].link = "link9"
        with self.assertRaises(mb.BadRequest) as refused:
            with self.client.control("irb1600", spec) as loop:
                for state in loop:
                    loop.send(effort=np.zeros(6))
        self.assertIn("sensor_points[1].link", str(refused.exception))

    def test_a_controller_asleep_past_the_timeout_fails_the_run(self):
        with self.client.control("irb1600", external(sampled_servo(), timeout_s=0.2)) as loop:
            for state in loop:
                if state.step == 2:
                    time.sleep(0.5)  # the controller's own behaviour, not an assertion
                loop.send(effort=np.zeros(6))
        self.assertEqual(loop.info.state, run_pb2.FAILED)
        self.assertIn("did not answer the state at t = 0.0002 s (step 2) within "
                      "control_timeout_s = 0.2 s", loop.info.message)

    def test_a_killed_controller_cancels_the_run_and_the_server_goes_on(self):
        script = (
            "import sys, numpy as np, mbstream_client as mb\n"
            "spec = {'duration_s': 1000, 'output_interval_s': 0.01, 'method': 'rk4',\n"
            "        'fixed_step_s': 0.001,\n"
            "        'drives': [{'external': {'period_s': 0.001}}] * 6}\n"
            "with mb.connect(sys.argv[1]) as c, c.control('irb1600', spec) as loop:\n"
            "    for state in loop:\n"
            "        if state.step == 10: print(loop.run_id, flush=True)\n"
            "        loop.send(effort=np.zeros(6))\n")
        child = subprocess.Popen([sys.executable, "-c", script, self.address],
                                 stdout=subprocess.PIPE, text=True)
        try:
            run_id = child.stdout.readline().strip()
            self.assertTrue(run_id.startswith("r-"), run_id)
            child.send_signal(signal.SIGKILL)
        finally:
            child.wait()
        info = self.client.get_run(run_id).wait()
        self.assertEqual(info.state, run_pb2.CANCELLED)
        self.assertIn("the controller's stream closed", info.message)
        self.assertEqual(self.client.run("irb1600", sampled_servo()).wait().state,
                         run_pb2.FINISHED)

    def test_a_nan_command_is_refused_and_the_run_stops(self):
        with self.assertRaises(mb.BadRequest) as caught:
            with self.client.control("irb1600", external(sampled_servo())) as loop:
                for state in loop:
                    loop.send(effort=[0, 0, float("nan"), 0, 0, 0] if state.step == 3
                              else np.zeros(6))
        self.assertIn("command.values[2] (joint 'joint3') is nan", caught.exception.message)
        info = self.client.get_run(loop.run_id).wait()
        self.assertEqual(info.state, run_pb2.FAILED)
        result = self.client.result(loop.run_id)
        self.assertTrue(np.all(np.isfinite(result.q)))

    def test_commands_by_joint_name_and_kind_checked(self):
        with self.client.control("irb1600", external(sampled_servo())) as loop:
            for state in loop:
                with self.assertRaises(mb.BadRequest):
                    loop.send(position=np.zeros(6))  # the drives take efforts
                loop.send({name: 0.0 for name in loop.external_joints})
                with self.assertRaises(mb.BadRequest):
                    loop.send(effort=np.zeros(6))  # one command per state
        self.assertEqual(loop.info.state, run_pb2.FINISHED, loop.info.message)


if __name__ == "__main__":
    unittest.main()
