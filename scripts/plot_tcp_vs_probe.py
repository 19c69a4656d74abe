#!/usr/bin/env python3
"""The seed's figure from a results directory: the simulated TCP and the viewer's probe
against time, x/y/z, aligned by frame sequence number, with the measured probe latency.

usage: /usr/bin/python3 scripts/plot_tcp_vs_probe.py --results DIR --out tcp_vs_probe.png
Prints the worst |probe - TCP| and the latency percentiles; exits 1 when a frame has no
probe report (or --tolerance is exceeded) so that scripts can check the link.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", required=True, help="results directory (tcp.csv, probes.csv)")
    parser.add_argument("--out", required=True, help="PNG to write")
    parser.add_argument("--probe", default=None, help="probe name (default: the first one)")
    parser.add_argument("--tolerance", type=float, default=1e-6, help="m, largest |probe - TCP|")
    args = parser.parse_args()

    tcp = np.loadtxt(f"{args.results}/tcp.csv", delimiter=",", skiprows=1, ndmin=2)
    try:
        with open(f"{args.results}/probes.csv") as f:
            rows = list(csv.DictReader(f))
    except FileNotFoundError:
        rows = []
    if not rows:
        print(f"no probe reports in {args.results} (was a viewer subscribed?)", file=sys.stderr)
        return 1
    name = args.probe or rows[0]["name"]
    rows = [r for r in rows if r["name"] == name]
    seq = np.array([int(r["seq"]) for r in rows])
    probe = np.array([[float(r["x"]), float(r["y"]), float(r["z"])] for r in rows])
    latency_ms = np.array([float(r["latency_us"]) for r in rows if float(r["latency_us"]) >= 0]) / 1e3
    missing = sorted(set(range(len(tcp))) - set(seq.tolist()))
    error = np.abs(probe - tcp[seq, 1:4]).max()
    p50 = np.median(latency_ms) if latency_ms.size else float("nan")
    p99 = np.percentile(latency_ms, 99) if latency_ms.size else float("nan")

    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 7))
    for i, axis in enumerate("xyz"):
        ax = axes[i]
        ax.plot(tcp[:, 0], tcp[:, 1 + i], color="tab:blue", lw=2.5, label="TCP (server)")
        ax.plot(tcp[seq, 0], probe[:, i], color="gold", lw=1.0, ls="--", label=f"probe '{name}' (viewer)")
        ax.set_ylabel(f"{axis} (m)")
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper right")
    axes[-1].set_xlabel("simulated time (s)")
    fig.suptitle(
        f"TCP vs probe, aligned by frame: max |diff| {error:.1e} m, "
        f"probe latency p50 {p50:.2f} ms, p99 {p99:.2f} ms\n"
        "(the seed's probe lagged two output delays, 100 ms)",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(
        f"{len(seq)} probe reports for {len(tcp)} frames, max |probe - TCP| {error:.3g} m, "
        f"latency p50 {p50:.3f} ms p99 {p99:.3f} ms; chart {args.out}"
    )
    if missing:
        print(f"{len(missing)} frames have no probe report (first: {missing[:5]})", file=sys.stderr)
        return 1
    if error > args.tolerance:
        print(f"probe and TCP differ by {error:.3g} m > {args.tolerance} m", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
