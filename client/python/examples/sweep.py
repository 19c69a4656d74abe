#!/usr/bin/env python3
"""A parameter sweep run concurrently on a live server: the IRB 1600 seed experiment
(models/irb1600/seed-run.json, integrated in joint space so that tolerances matter) over
several relative tolerances, or over scaled drive amplitudes, all runs in flight at once;
prints a table of the TCP error (against the closed-form kinematics, from the run's stats)
and the CPU time.

    sweep.py --server ADDR [--sweep rtol|amplitude] [--values V,V,...] [--duration S]
"""
import argparse
import sys

import _common
import mbstream_client as mb

DEFAULTS = {"rtol": "1e-3,1e-4,1e-5,1e-6,1e-7,1e-8,1e-9,1e-10", "amplitude": "0.25,0.5,1,1.5,2"}


def scaled_drives(spec, scale):
    """The spec's drives with every sine amplitude multiplied by `scale`."""
    drives = []
    for drive in spec.drives:
        copy = type(drive)()
        copy.CopyFrom(drive)
        drive = copy
        for term in drive.prescribed.trajectory.sum_of_sines.terms:
            term.amplitude *= scale
        drives.append(drive)
    return drives


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    _common.add_server_argument(parser)
    parser.add_argument("--sweep", choices=sorted(DEFAULTS), default="rtol")
    parser.add_argument("--values", help="comma-separated values (default: %s)" % DEFAULTS)
    parser.add_argument("--rtol", type=float, default=1e-6, help="rtol of an amplitude sweep")
    parser.add_argument("--duration", type=float, default=20.0, help="s, simulated per run")
    args = parser.parse_args()
    values = [float(v) for v in (args.values or DEFAULTS[args.sweep]).split(",")]

    base = mb.load_spec(_common.model_file("irb1600", "seed-run.json"), formulation="joint",
                        duration=args.duration)
    with mb.connect(args.server, ca_file=args.ca, token=args.token) as server:
        specs = []
        for value in values:  # every run started in one call, then collected in one
            if args.sweep == "rtol":
                overrides = {"rtol": value, "atol": value / 100}
            else:
                overrides = {"rtol": args.rtol, "atol": args.rtol / 100,
                             "drives": scaled_drives(base, value)}
            specs.append(mb.load_spec(base, **overrides))
        runs = server.run_many("irb1600", specs)
        results = server.results(runs)

    print("irb1600 seed-run, joint space, %g s simulated, %d runs at once"
          % (args.duration, len(runs)))
    print("%-10s %-24s %-9s %12s %10s %7s %9s" % (args.sweep, "run", "state", "tcp_err_m",
                                                   "cpu_ms", "steps", "rhs_evals"))
    for value, result in zip(values, results):
        s = result.stats
        print("%-10g %-24s %-9s %12.3e %10.3f %7d %9d" % (
            value, result.run_id, result.state, s["tcp_error_max_m"], s["cpu_s"] * 1e3,
            s["steps"], s["rhs_evals"]))
    failed = [r for r in results if not r.finished]
    for r in failed:
        print("run %s %s: %s" % (r.run_id, r.state, r.message), file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
