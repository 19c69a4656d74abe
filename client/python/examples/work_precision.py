#!/usr/bin/env python3
"""The speed-accuracy (work-precision) chart from runs on a live server: the IRB 1600 servo
scene (models/irb1600/seed-servo.json) with several integration methods x tolerances, all
runs in flight at once; the error of each is its largest TCP distance from a reference run
(CVODE BDF at rtol 1e-12, atol 1e-14) over the output frames, against the CPU time the
server measured. Prints the table and saves the chart as a PNG (matplotlib, Agg backend).

    work_precision.py --server ADDR [--methods bdf,adams,erk,dirk] [--rtols 1e-3,...]
                      [--duration S] [--out work_precision.png]

With --target M it asks instead for an accuracy: each of the four reference scenes
(seed-run, seed-servo, passive-swing, stiff-servo) runs with "target": {"tcp_error_m": M} and
method "auto", and the server's choice (method, tolerance, why, the CPU time of choice + run +
check) and its verification (the achieved error, target met or not) are printed:

    work_precision.py --server ADDR --target 1e-5 [--duration S]
"""
import argparse
import concurrent.futures
import json
import sys

import numpy as np

import _common
import mbstream_client as mb

REFERENCE = {"method": "bdf", "rtol": 1e-12, "atol": 1e-14}
SCENES = ("seed-run", "seed-servo", "passive-swing", "stiff-servo")


def run_targets(args):
    """--target: each scene with an accuracy target; print the choice and its verification."""
    with mb.connect(args.server, ca_file=args.ca, token=args.token) as server:
        runs = {}
        for scene in SCENES:
            overrides = {"duration": args.duration} if args.duration_given else {}
            spec = mb.load_spec(_common.model_file("irb1600", scene + ".json"),
                                target={"tcp_error_m": args.target}, method="auto",
                                **overrides)
            runs[scene] = server.run("irb1600", spec)
        results = {scene: run.result() for scene, run in runs.items()}
    print("TCP target %g m" % args.target)
    print("%-14s %-9s %-24s %10s %-10s %10s" % ("scene", "state", "choice", "achieved_m",
                                                 "target_met", "cpu_ms"))
    for scene, result in results.items():
        stats = result.stats
        choice = json.loads(stats["choice_json"]) if stats.get("choice_json") else {}
        pick = choice.get("pick", {})
        if pick.get("method", "none") == "none":
            what = "closed form"
        else:
            what = "%s%s rtol %.1e" % (pick["method"],
                                       "-" + pick["erk_table"] if pick.get("erk_table") else "",
                                       pick["rtol"])
        check = choice.get("verification", {})
        achieved = (check.get("achieved") or {}).get("tcp_m")
        met = stats.get("target_met")
        print("%-14s %-9s %-24s %10s %-10s %10.2f" % (
            scene, result.state, what, "%.2e" % achieved if achieved is not None else "-",
            "not verified" if met is None else str(met).lower(),
            1e3 * choice.get("cpu_s", {}).get("total", 0.0)))
        print("    why: %s" % choice.get("reason", ""))
        print("    check: %s" % check.get("how", ""))
        if stats.get("message"):
            print("    message: %s" % stats["message"])
    return 0 if all(r.finished for r in results.values()) else 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    _common.add_server_argument(parser)
    parser.add_argument("--methods", default="bdf,adams,erk,dirk",
                        help="adaptive methods (comma-separated)")
    parser.add_argument("--rtols", default="1e-3,1e-4,1e-5,1e-6,1e-7,1e-8",
                        help="relative tolerances (atol = rtol / 100)")
    parser.add_argument("--duration", type=float, default=5.0, help="s, simulated per run")
    parser.add_argument("--out", default="work_precision.png", help="PNG file to write")
    parser.add_argument("--target", type=float,
                        help="m: instead of the chart, run each reference scene with this TCP "
                             "accuracy target and print the choice and its verification")
    args = parser.parse_args()
    args.duration_given = "--duration" in sys.argv
    if args.target is not None:
        return run_targets(args)
    methods = args.methods.split(",")
    rtols = [float(r) for r in args.rtols.split(",")]
    spec = mb.load_spec(_common.model_file("irb1600", "seed-servo.json"), duration=args.duration)

    with mb.connect(args.server, ca_file=args.ca, token=args.token) as server:
        reference_run = server.run("irb1600", spec, **REFERENCE)
        runs = {(m, r): server.run("irb1600", spec, method=m, rtol=r, atol=r / 100)
                for m in methods for r in rtols}
        with concurrent.futures.ThreadPoolExecutor(8) as pool:
            reference = pool.submit(reference_run.result, check=True)
            results = dict(zip(runs, pool.map(lambda run: run.result(), runs.values())))
            reference = reference.result()

    print("irb1600 seed-servo, %g s simulated; error = max TCP distance from the reference "
          "(%s rtol %g, %.3f s CPU)" % (args.duration, REFERENCE["method"], REFERENCE["rtol"],
                                        reference.stats["cpu_s"]))
    print("%-6s %8s %-19s %12s %10s %8s" % ("method", "rtol", "state", "error_m", "cpu_ms",
                                            "steps"))
    points = {m: [] for m in methods}
    for (method, rtol), result in results.items():
        n = min(len(result.t), len(reference.t))
        error = (np.linalg.norm(result.tcp[:n] - reference.tcp[:n], axis=1).max()
                 if n else float("nan"))
        cpu = result.stats["cpu_s"]
        print("%-6s %8.0e %-19s %12.3e %10.3f %8d" % (method, rtol, result.state, error,
                                                      cpu * 1e3, result.stats["steps"]))
        if result.finished:
            points[method].append((cpu, max(error, 1e-16), rtol))

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axis = plt.subplots(figsize=(7, 5))
    for method, rows in points.items():
        if not rows:
            continue
        cpu, error, rtol = zip(*rows)
        axis.loglog(cpu, error, "o-", label=method)
        for x, y, r in rows:
            axis.annotate("%.0e" % r, (x, y), fontsize=7, xytext=(3, 3),
                          textcoords="offset points")
    axis.set_xlabel("CPU time (s)")
    axis.set_ylabel("max TCP error (m)")
    axis.set_title("Work-precision, irb1600 seed-servo, %g s (from server %s)"
                   % (args.duration, args.server), fontsize=10)
    axis.grid(True, which="both", alpha=0.3)
    axis.legend()
    figure.tight_layout()
    figure.savefig(args.out, dpi=100)
    print("wrote %s" % args.out)
    failed = sum(1 for r in results.values() if not r.finished)
    if failed:
        print("%d run(s) did not finish (state above)" % failed, file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
