#!/usr/bin/env python3
"""Result.to_mcap, Run.to_mcap and Client.export_mcap against a live mbstream-server
($MBSTREAM_SERVER): the file the server writes is read back by the independent reader of the
C++ tests (tests/server/mcap/reader/read_mcap.js: @mcap/core, every CRC, Foxglove's CDR
decoder) and every joint value compared, bit for bit, with the run's CSV files as
`mbstream result RUN --out` ($MBSTREAM_CLI) writes them. ctest runs it through
run_with_server.py."""
import datetime
import json
import os
import subprocess
import tempfile
import unittest

import mbstream_client as mb

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
SEED_SERVO = os.path.join(ROOT, "models", "irb1600", "seed-servo.json")
URDF = os.path.join(ROOT, "models", "irb1600", "irb1600.urdf")
READER = os.path.join(ROOT, "tests", "server", "mcap", "reader", "read_mcap.js")


class McapTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.address = os.environ.get("MBSTREAM_SERVER")
        cls.cli = os.environ.get("MBSTREAM_CLI")
        if not cls.address or not cls.cli:
            raise unittest.SkipTest("set MBSTREAM_SERVER and MBSTREAM_CLI (ctest does)")
        if not os.path.isdir(os.path.join(os.path.dirname(READER), "node_modules")):
            raise unittest.SkipTest("tests/server/mcap/reader/node_modules missing "
                                    "(scripts/setup.sh installs it)")
        cls.client = mb.connect(cls.address)
        cls.tmp = tempfile.TemporaryDirectory()

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.tmp.cleanup()

    def path(self, name):
        return os.path.join(self.tmp.name, name)

    def csvs(self, run_id):
        """The run's results directory as the CLI writes it."""
        out = self.path("results-" + run_id)
        subprocess.run([self.cli, "--server", self.address, "result", run_id, "--out", out],
                       check=True, capture_output=True)
        return out

    def read(self, mcap, results, start_ns):
        read = subprocess.run(["node", READER, mcap, results, str(start_ns), URDF, "tcp"],
                              capture_output=True, text=True, cwd=ROOT)
        self.assertEqual(read.returncode, 0, read.stdout + read.stderr)
        return json.loads(read.stdout)

    def test_result_to_mcap_reads_back_as_the_runs_csv_files(self):
        result = self.client.run("irb1600", SEED_SERVO, duration=2).result(check=True)
        start = datetime.datetime(2026, 11, 26, 12, 0, 0, 250000,
                                  tzinfo=datetime.timezone.utc)
        path = result.to_mcap(self.path("servo.mcap"), compression="lz4", start=start)
        self.assertFalse(os.path.exists(path + ".tmp"))
        summary = self.read(path, self.csvs(result.run_id), 1795694400250000000)
        self.assertEqual(summary["frames"], len(result.t))
        self.assertEqual(summary["frames"], 41)
        self.assertEqual(summary["compression"], "lz4")
        self.assertTrue(summary["has_effort"])
        self.assertEqual(summary["names"], result.joint_names)
        self.assertEqual(len(summary["tf"]), 6)
        self.assertLess(summary["tcp_error_max_m"], 1e-12)

    def test_export_by_id_stamps_from_the_runs_start(self):
        run = self.client.run("irb1600", SEED_SERVO, duration=1)
        path = self.client.export_mcap(run.id, self.path("by-id.mcap"))  # waits for the end
        info = self.client.get_run(run.id).info
        summary = self.read(path, self.csvs(run.id), info.started_unix_ms * 1000000)
        self.assertEqual(summary["frames"], 21)
        self.assertEqual(summary["compression"], "zstd")
        self.assertEqual(run.to_mcap(self.path("by-run.mcap"), compression="none",
                                     start=1795694400.5), self.path("by-run.mcap"))
        self.assertEqual(self.read(self.path("by-run.mcap"), self.csvs(run.id),
                                   1795694400500000000)["compression"], "")

    def test_errors_leave_no_file(self):
        with self.assertRaises(mb.NotFound):
            self.client.export_mcap("r-none", self.path("none.mcap"))
        self.assertFalse(os.path.exists(self.path("none.mcap")))
        self.assertFalse(os.path.exists(self.path("none.mcap.tmp")))
        run = self.client.run("irb1600", SEED_SERVO, duration=0.5)
        run.wait()
        with self.assertRaisesRegex(mb.BadRequest, "2026-02-30"):
            run.to_mcap(self.path("bad.mcap"), start="2026-02-30T00:00:00Z")
        with self.assertRaisesRegex(ValueError, "zstd, lz4, none"):
            run.to_mcap(self.path("bad.mcap"), compression="gzip")
        self.assertFalse(os.path.exists(self.path("bad.mcap")))
        running = self.client.run("irb1600", SEED_SERVO, duration=60, realtime=1)
        with self.assertRaises(mb.FailedPrecondition):  # 60 s of wall time to its end
            running.to_mcap(self.path("running.mcap"), wait=False)
        running.cancel()
        self.assertFalse(os.path.exists(self.path("running.mcap")))
        result = run.result()
        result._stub = None  # a Result built by hand
        with self.assertRaisesRegex(ValueError, "export_mcap"):
            result.to_mcap(self.path("bad.mcap"))


if __name__ == "__main__":
    unittest.main()
