#!/usr/bin/env python3
"""Free bodies from Python against a real mbstream-server (run_with_server.py, issue 43): a
URDF submitted with floating_base=True gets a free joint named after its root link and falls;
a run spec given as a dict places a world's box by its name (initial_bodies) and the box flies
on its parabola from there; a name that is no free body is refused (BadRequest) naming it."""
import math
import os
import unittest

import numpy as np

import mbstream_client as mb
from server_case import ServerTestCase

ATLAS = "/usr/share/doc/dart/data/sdf/atlas/atlas_v3_no_head.urdf"
G = 9.81  # m/s^2, the specs'
FALL = {"duration_s": 0.2, "output_interval_s": 0.02, "method": "bdf", "rtol": 1e-10,
        "atol": 1e-12, "gravity": {"z": -G}, "contact": {"enabled": False}}
FREE = [".x", ".y", ".z", ".qw", ".qx", ".qy", ".qz"]


class FreeBodyTest(ServerTestCase):
    def test_a_floating_base_urdf_falls_from_a_pose_given_by_name(self):
        if not os.path.exists(ATLAS):
            self.skipTest(ATLAS + " is missing (Debian's dart-doc)")
        info = self.client.submit(ATLAS, name="atlas_free", floating_base=True)
        self.assertEqual(list(info.position_names[:7]), ["pelvis" + s for s in FREE])
        spec = dict(FALL, initial_bodies=[{"name": "pelvis", "position_m": {"z": 1.0},
                                           "rpy": {"yaw": 0.5}}])
        result = self.client.run("atlas_free", spec).result(check=True)
        self.assertEqual(result.q.shape, (11, 7 + 27))
        z = result.q[:, result.position("pelvis.z")]
        np.testing.assert_allclose(z, 1.0 - 0.5 * G * result.t ** 2, rtol=0, atol=1e-8)
        qw = result.q[:, result.position("pelvis.qw")]
        qz = result.q[:, result.position("pelvis.qz")]
        np.testing.assert_allclose(qw, math.cos(0.25), rtol=0, atol=1e-10)
        np.testing.assert_allclose(qz, math.sin(0.25), rtol=0, atol=1e-10)
        self.assertLessEqual(np.max(np.abs(result.q[:, 7:])), 1e-8)  # no joint moves

    def test_a_worlds_box_is_thrown_by_its_name(self):
        self.client.submit(os.path.join("models", "worlds", "irb1600_table"), name="boxes")
        spec = dict(FALL, initial_bodies=[{"name": "box_c::link",
                                           "positionM": {"x": 2, "y": 1, "z": 3},
                                           "linearVelocityMPerS": {"y": -1, "z": 1}}])
        result = self.client.run("boxes", spec).result(check=True)
        t = result.t
        box = {s: result.q[:, result.position("box_c::link" + s)] for s in FREE}
        np.testing.assert_allclose(box[".x"], 2.0, rtol=0, atol=1e-8)
        np.testing.assert_allclose(box[".y"], 1.0 - t, rtol=0, atol=1e-8)
        np.testing.assert_allclose(box[".z"], 3.0 + t - 0.5 * G * t ** 2, rtol=0, atol=1e-8)
        # Its orientation is the world's (a roll of 0.3 rad), untouched by the entry.
        np.testing.assert_allclose(box[".qx"], math.sin(0.15), rtol=0, atol=1e-10)
        with self.assertRaises(mb.BadRequest) as refused:
            self.client.run("boxes", dict(FALL, initial_bodies=[{"name": "box_d::link"}]))
        self.assertIn("initial_bodies[0].name: 'box_d::link' is no free body", str(refused.exception))
        self.assertIn("box_a::link, box_b::link, box_c::link", str(refused.exception))


if __name__ == "__main__":
    unittest.main()
