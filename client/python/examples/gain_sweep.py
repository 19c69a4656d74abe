#!/usr/bin/env python3
"""A sweep of servo gains, notebook style (client/python/README.md shows it cell by cell):
the IRB 1600 servo scene (models/irb1600/seed-servo.json) with every joint's PD gains scaled,
kd kept at critical damping of a unit inertia (kd = 2 sqrt(kp)), all runs at once; then the
tracking error of one joint (q - q_ref, rad) against time for each gain, and the largest
error per gain in a table. Saves the figure as a PNG.

    gain_sweep.py --server ADDR [--kp 100,400,1600,6400] [--joint NAME] [--duration S]
                  [--out gain_sweep.png]
"""
import argparse
import concurrent.futures
import math
import sys

import numpy as np

import _common
import mbstream_client as mb


def with_gains(spec, kp):
    """The spec's drives with kp, and kd = 2 sqrt(kp), on every PD servo."""
    drives = []
    for drive in spec.drives:
        copy = type(drive)()
        copy.CopyFrom(drive)
        copy.pd_servo.kp = kp
        copy.pd_servo.kd = 2.0 * math.sqrt(kp)
        drives.append(copy)
    return drives


def reference(drive, t):
    """q_ref(t) of a sum-of-sines drive, rad."""
    sines = drive.pd_servo.trajectory.sum_of_sines
    return sines.offset + sum(s.amplitude * np.sin(s.omega * t + s.phase) for s in sines.terms)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    _common.add_server_argument(parser)
    parser.add_argument("--kp", default="100,400,1600,6400", help="N*m/rad, comma-separated")
    parser.add_argument("--joint", help="the joint to plot (default: the model's second)")
    parser.add_argument("--duration", type=float, default=5.0, help="s, simulated per run")
    parser.add_argument("--out", default="gain_sweep.png", help="PNG file to write")
    args = parser.parse_args()
    gains = [float(k) for k in args.kp.split(",")]

    # Cell 1: connect, submit the robot, start one run per gain (they run concurrently).
    spec = mb.load_spec(_common.model_file("irb1600", "seed-servo.json"),
                        duration=args.duration)
    with mb.connect(args.server, ca_file=args.ca, token=args.token) as server:
        server.submit(_common.model_file("irb1600"))
        runs = {kp: server.run("irb1600", spec, drives=with_gains(spec, kp)) for kp in gains}
        # Cell 2: wait for all of them and fetch the results (NumPy arrays, joint names).
        with concurrent.futures.ThreadPoolExecutor(len(runs)) as pool:
            results = dict(zip(runs, pool.map(lambda r: r.result(check=True), runs.values())))

    # Cell 3: tracking error of one joint, by name.
    first = next(iter(results.values()))
    joint = args.joint or first.joint_names[1]
    j = first.joint(joint)
    print("irb1600 seed-servo, %g s simulated, joint %s; kd = 2 sqrt(kp)"
          % (args.duration, joint))
    print("%10s %10s %-24s %14s %10s" % ("kp", "kd", "run", "max|e|_rad", "cpu_ms"))
    errors = {}
    for kp, result in results.items():
        errors[kp] = result.q[:, j] - reference(spec.drives[j], result.t)
        print("%10g %10.3g %-24s %14.3e %10.3f" % (kp, 2 * math.sqrt(kp), result.run_id,
                                                   np.abs(errors[kp]).max(),
                                                   result.stats["cpu_s"] * 1e3))

    # Cell 4: the plot.
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for kp, result in results.items():
        top.plot(result.t, errors[kp], label="kp %g" % kp)
    top.set_ylabel("%s: q - q_ref (rad)" % joint)
    top.set_title("Servo gain sweep, irb1600 seed-servo (kd = 2 sqrt(kp))", fontsize=10)
    top.grid(True, alpha=0.3)
    top.legend(fontsize=8)
    biggest = results[max(gains)]
    for kp, result in results.items():
        bottom.plot(result.t, result.tau[:, j], label="kp %g" % kp)
    bottom.set_xlabel("t (s)")
    bottom.set_ylabel("%s: tau (N*m)" % joint)
    bottom.grid(True, alpha=0.3)
    figure.tight_layout()
    figure.savefig(args.out, dpi=100)
    print("wrote %s (%d frames per run, joints %s)"
          % (args.out, len(biggest.t), ", ".join(biggest.joint_names)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
