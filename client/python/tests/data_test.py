#!/usr/bin/env python3
"""Tests of the data calls of mbstream_client against a live mbstream-server
($MBSTREAM_SERVER): delete_runs (a running run cancelled first, every read of a deleted run
NotFound), delete_model (refused while it has runs, unless with_runs), keep and
retention_plan (the server keeps the newest 2 ended runs: --retain-runs=2, one pass at start).
ctest runs them through run_with_server.py."""
import os
import unittest

import mbstream_client as mb

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
IRB = os.path.join(ROOT, "models", "irb1600")
SEED_RUN = os.path.join(IRB, "seed-run.json")


class DataTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        address = os.environ.get("MBSTREAM_SERVER")
        if not address:
            raise unittest.SkipTest("set MBSTREAM_SERVER (run_with_server.py does)")
        cls.client = mb.connect(address)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()

    def test_delete_runs_cancels_a_running_run_and_every_read_is_not_found(self):
        ended = self.client.run("irb1600", SEED_RUN)
        ended.wait()
        running = self.client.run("irb1600", SEED_RUN, duration=1000, realtime=1)
        deleted = self.client.delete_runs([ended, running.id])
        self.assertEqual([info.id for info in deleted], [ended.id, running.id])
        self.assertEqual(mb.run_pb2.RunState.Name(deleted[0].state), "FINISHED")
        self.assertEqual(mb.run_pb2.RunState.Name(deleted[1].state), "CANCELLED")
        for run_id in (ended.id, running.id):
            with self.assertRaises(mb.NotFound):
                self.client.get_run(run_id)
            with self.assertRaises(mb.NotFound):
                self.client.probe_sets(run_id)
        self.assertNotIn(ended.id, [info.id for info in self.client.runs()])
        with self.assertRaises(mb.NotFound) as caught:
            self.client.delete_runs(["r-nothing"])
        self.assertIn("r-nothing", caught.exception.message)

    def test_delete_model_needs_with_runs_while_it_has_runs(self):
        bundle = mb.read_model_bundle(IRB)
        bundle.name = "python-delete-me"
        bundle.urdf += "<!-- python data test -->\n"
        model = self.client.submit_bundle(bundle)
        run = self.client.run(model.id, SEED_RUN)
        run.wait()
        with self.assertRaises(mb.FailedPrecondition) as caught:
            self.client.delete_model("python-delete-me")
        self.assertIn("--with-runs", caught.exception.message)
        response = self.client.delete_model("python-delete-me", with_runs=True)
        self.assertEqual(response.model.id, model.id)
        self.assertEqual([info.id for info in response.runs], [run.id])
        self.assertNotIn(model.id, [m.id for m in self.client.models()])
        with self.assertRaises(mb.NotFound):
            self.client.get_run(run.id)
        with self.assertRaises(mb.FailedPrecondition):
            self.client.delete_model("irb1600")  # built in

    def test_keep_and_the_retention_dry_run(self):
        runs = [self.client.run("irb1600", SEED_RUN, duration=0.2) for _ in range(3)]
        for run in runs:
            run.wait()
        with self.assertRaises(mb.FailedPrecondition):  # not ended yet
            self.client.keep(self.client.run("irb1600", SEED_RUN, duration=1000, realtime=1))
        self.assertTrue(self.client.keep(runs[0]).keep)
        self.assertTrue(self.client.get_run(runs[0].id).info.keep)
        plan = self.client.retention_plan()
        self.assertEqual(plan.retain_runs, 2)
        self.assertEqual(plan.retain_days, 0)
        # What a pass would delete: the ended runs not kept, beyond the newest two, oldest first.
        ended = [info for info in self.client.runs()
                 if mb.run_pb2.RunState.Name(info.state) in ("FINISHED", "FAILED", "CANCELLED",
                                                                "INTERRUPTED")
                 and not info.keep]
        self.assertEqual([info.id for info in plan.runs], [info.id for info in ended[2:]][::-1])
        self.assertNotIn(runs[0].id, [info.id for info in plan.runs])
        self.assertIn(runs[0].id, [info.id for info in self.client.runs()])  # nothing deleted
        self.assertFalse(self.client.keep(runs[0].id, keep=False).keep)
        self.assertIn(runs[0].id, [info.id for info in self.client.retention_plan().runs])


if __name__ == "__main__":
    unittest.main()
