#!/usr/bin/env python3
"""Tests of the replay side of mbstream_client against a live mbstream-server
($MBSTREAM_SERVER): a replay's probe set (probe_sets, result(probe_set=...)) and compare().
ctest runs them through run_with_server.py."""
import os
import queue
import unittest

import numpy as np

import mbstream_client as mb
from server_case import ServerTestCase
from mbstream_client import simulation_service_pb2 as service_pb2

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
SEED_SERVO = os.path.join(ROOT, "models", "irb1600", "seed-servo.json")


def replay_answering_probes(client, run_id, viewer):
    """A stand-in for a replaying viewer: replays `run_id` unpaced, answers every frame with
    a probe at its TCP, half-closes after run_ended. Returns the replay's probe set id."""
    replies = queue.Queue()

    def requests():
        start = service_pb2.SubscribeRequest()
        start.start.run_id = run_id
        start.start.replay.speed = 0.0
        start.start.replay.viewer = viewer
        start.start.replay.scene = "test scene"
        yield start
        while True:
            reply = replies.get()
            if reply is None:
                return
            yield reply

    probe_set = None
    for event in client.stub.Subscribe(requests()):
        kind = event.WhichOneof("event")
        if kind == "replay_state":
            probe_set = event.replay_state.probe_set
        elif kind == "frames":
            for frame in event.frames.frames:
                reply = service_pb2.SubscribeRequest()
                reply.probe.seq = frame.seq
                reply.probe.probe = "tcp"
                reply.probe.position_m.CopyFrom(frame.tcp_m)
                reply.probe.frame = "World"
                replies.put(reply)
        elif kind == "run_ended":
            replies.put(None)
    return probe_set


class ReplayTest(ServerTestCase):

    def test_each_replays_probe_set_can_be_fetched(self):
        run = self.client.run("irb1600", SEED_SERVO, duration=1)
        run.wait()
        first = replay_answering_probes(self.client, run.id, "viewer-1")
        second = replay_answering_probes(self.client, run.id, "viewer-2")
        sets = self.client.probe_sets(run.id)
        self.assertEqual([s.id for s in sets], [first, second])
        self.assertEqual([s.viewer for s in sets], ["viewer-1", "viewer-2"])
        self.assertEqual([s.reports for s in sets], [21, 21])
        result = self.client.result(run.id, probe_set=second)
        np.testing.assert_array_equal(result.probe("tcp")["x"], result.tcp[:, 0])
        self.assertEqual(len(self.client.result(run.id).probes), 0)  # the live run's: none
        with self.assertRaises(mb.NotFound):
            self.client.result(run.id, probe_set="ps-0000000000000000")

    def test_compare_gives_the_tcp_distance_on_the_common_grid(self):
        bdf = self.client.run("irb1600", SEED_SERVO, duration=1).result(check=True)
        euler = self.client.run("irb1600", SEED_SERVO, duration=1, output_interval=0.01,
                                method="euler", step=1e-4).result(check=True)
        comparison = self.client.compare(bdf.run_id, euler.run_id)
        self.assertEqual((comparison.stride, comparison.ghost_stride), (1, 5))
        self.assertEqual(len(comparison.t), 21)
        np.testing.assert_array_equal(comparison.ghost_tcp, euler.tcp[::5])
        expected = np.linalg.norm(bdf.tcp - euler.tcp[::5], axis=1)
        np.testing.assert_allclose(comparison.distance, expected, rtol=1e-15)
        self.assertEqual(comparison.max_distance, comparison.distance.max())
        odd = self.client.run("irb1600", SEED_SERVO, duration=1, output_interval=0.03).result()
        with self.assertRaisesRegex(ValueError, "time grids cannot be aligned"):
            self.client.compare(bdf.run_id, odd.run_id)


if __name__ == "__main__":
    unittest.main()
