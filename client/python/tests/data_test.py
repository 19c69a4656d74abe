#!/usr/bin/env python3
"""Tests of the data calls of mbstream_client against a live mbstream-server
($MBSTREAM_SERVER): delete_runs (a running run cancelled first, every read of a deleted run
NotFound), delete_model (refused while it has runs, unless with_runs), keep and
retention_plan (the server keeps the newest 2 ended runs: --retain-runs=2, one pass at start),
storage and backup.
ctest runs them through run_with_server.py."""
import os
import shutil
import tempfile
import unittest

import mbstream_client as mb
from server_case import ServerTestCase

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
IRB = os.path.join(ROOT, "models", "irb1600")
SEED_RUN = os.path.join(IRB, "seed-run.json")


class DataTest(ServerTestCase):

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

    def test_storage_and_a_backup(self):
        run = self.client.run("irb1600", SEED_RUN, duration=0.2)
        run.wait()
        storage = self.client.storage()
        self.assertEqual(storage.backend, "sqlite")
        self.assertGreater(storage.frame_bytes, 0)
        self.assertGreater(storage.disk_bytes, 0)
        self.assertGreater(storage.free_bytes, 0)
        self.assertEqual(storage.min_free_bytes, 64 << 20)
        self.assertFalse(storage.below_min_free)
        by_state = {mb.run_pb2.RunState.Name(c.state): c.runs for c in storage.runs}
        self.assertGreaterEqual(by_state["FINISHED"], 1)
        self.assertEqual(sum(by_state.values()), len(self.client.runs()))
        irb = [m for m in storage.models if m.model_name == "irb1600"]
        self.assertEqual(len(irb), 1)
        self.assertGreater(irb[0].frame_bytes, 0)
        self.assertEqual(storage.retain_runs, 2)
        self.assertEqual(storage.retention_runs, len(self.client.retention_plan().runs))

        directory = os.path.join(tempfile.mkdtemp(), "backup")
        backup = self.client.backup(directory)
        self.assertEqual(backup.dir, directory)
        self.assertGreaterEqual(backup.runs, 1)
        self.assertTrue(os.path.exists(os.path.join(directory, "mbstream.sqlite3")))
        self.assertEqual(os.path.getsize(os.path.join(directory, "mbstream.frames")),
                         backup.frames_bytes)
        with self.assertRaises(mb.BadRequest) as caught:  # never over another backup
            self.client.backup(directory)
        self.assertIn("not empty", caught.exception.message)
        shutil.rmtree(os.path.dirname(directory))


if __name__ == "__main__":
    unittest.main()
