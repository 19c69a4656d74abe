#!/usr/bin/env python3
"""The client against a real mbstream-server started with --token-file tests/tokens.txt: no
token -> Unauthenticated, a view token running -> PermissionDenied, each with the server's
message; the version check at connect needs no token (reflection is not a Simulation call).

ctest runs it through run_with_server.py with the venv's python (client/python/CMakeLists.txt).
"""
import os
import unittest

import mbstream_client as mb

VIEW = "python-test-view-token-0001"
RUN = "python-test-run-token-00001"


class AuthTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.address = os.environ.get("MBSTREAM_SERVER")
        if not cls.address:
            raise unittest.SkipTest("set MBSTREAM_SERVER (run_with_server.py does)")

    def test_no_token_is_unauthenticated(self):
        with mb.connect(self.address) as client:  # the check at connect needs no token
            self.assertIn("mbstream.v1.Simulation", client.server.services)
            with self.assertRaises(mb.Unauthenticated) as caught:
                client.models()
        self.assertEqual(caught.exception.code, "UNAUTHENTICATED")
        self.assertTrue(caught.exception.message)

    def test_a_wrong_token_is_unauthenticated(self):
        with mb.connect(self.address, token="not-a-token-of-this-server") as client:
            with self.assertRaises(mb.Unauthenticated):
                client.models()

    def test_a_view_token_cannot_control_a_run(self):
        spec = {"duration_s": 0.01, "drives": [{"external": {"period_s": 0.001}}]}
        with mb.connect(self.address, token=VIEW) as client:
            with self.assertRaises(mb.PermissionDenied) as caught:
                client.control("irb1600", spec)
        self.assertIn("run", caught.exception.message)

    def test_a_view_token_may_list_but_not_run(self):
        with mb.connect(self.address, token=VIEW) as client:
            client.models()
            with self.assertRaises(mb.PermissionDenied) as caught:
                client.run("irb1600", duration=0.1)
        self.assertEqual(caught.exception.code, "PERMISSION_DENIED")
        self.assertIn("lacks the role 'run'", caught.exception.message)

    def test_a_view_token_may_not_delete(self):
        with mb.connect(self.address, token=RUN) as client:
            run = client.run("irb1600", "models/irb1600/seed-run.json", duration=0.1)
            run.wait()
        with mb.connect(self.address, token=VIEW) as client:
            with self.assertRaises(mb.PermissionDenied) as caught:
                client.delete_runs([run])
            self.assertIn("lacks the role 'admin'", caught.exception.message)
            self.assertEqual(client.get_run(run.id).id, run.id)  # still there

    def test_a_run_token_runs(self):
        with mb.connect(self.address, token=RUN) as client:
            result = client.run("irb1600", "models/irb1600/seed-run.json",
                                duration=0.5).result(check=True)
        self.assertEqual(result.t.shape, (11,))


if __name__ == "__main__":
    unittest.main()
