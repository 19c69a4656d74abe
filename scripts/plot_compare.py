#!/usr/bin/env python3
"""The demo's second figure: the distance between two runs' TCPs against time, on their
common time grid (the times both runs have, as mbstream-viewer --compare shows them).

usage: /usr/bin/python3 scripts/plot_compare.py --run DIR --ghost DIR --out compare.png
       [--label-run BDF] [--label-ghost EULER]
DIR: results directories (tcp.csv, stats.json). Prints the maximum distance and when it was.
"""
import argparse
import json
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--run", required=True, help="results directory of the run")
    parser.add_argument("--ghost", required=True, help="results directory of the ghost")
    parser.add_argument("--out", required=True, help="PNG to write")
    parser.add_argument("--label-run", default=None)
    parser.add_argument("--label-ghost", default=None)
    args = parser.parse_args()

    run = np.loadtxt(f"{args.run}/tcp.csv", delimiter=",", skiprows=1, ndmin=2)
    ghost = np.loadtxt(f"{args.ghost}/tcp.csv", delimiter=",", skiprows=1, ndmin=2)
    # The common grid: times of both runs equal to 1e-9 s.
    keys_run = {round(t * 1e9): i for i, t in enumerate(run[:, 0])}
    pairs = [(keys_run[round(t * 1e9)], j) for j, t in enumerate(ghost[:, 0])
             if round(t * 1e9) in keys_run]
    if len(pairs) < 2:
        print("the two runs share fewer than 2 output times: their grids cannot be aligned",
              file=sys.stderr)
        return 1
    rows, ghost_rows = np.array(pairs).T
    t = run[rows, 0]
    distance = np.linalg.norm(run[rows, 1:4] - ghost[ghost_rows, 1:4], axis=1)

    def label(directory, given):
        if given:
            return given
        with open(f"{directory}/stats.json") as f:
            stats = json.load(f)
        return f"{stats.get('method', '?')} ({stats.get('formulation', '?')})"

    k = int(np.argmax(distance))
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(t, 1e3 * distance, color="tab:blue")
    ax.plot(t[k], 1e3 * distance[k], "o", color="tab:red")
    ax.annotate(f"max {1e3 * distance[k]:.3g} mm at t = {t[k]:.2f} s", (t[k], 1e3 * distance[k]),
                textcoords="offset points", xytext=(-150, -15), fontsize=9)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("|TCP - ghost TCP| (mm)")
    ax.set_title(f"{label(args.run, args.label_run)} against the ghost "
                 f"{label(args.ghost, args.label_ghost)}: TCP distance", fontsize=10)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"{len(t)} common times, max |TCP - ghost TCP| {distance[k]:.6g} m at t = {t[k]:.3f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
