#!/usr/bin/python3
"""Time per call of inverse dynamics (RNEA), forward dynamics (ABA) and the mass matrix (CRBA)
against the joint count: generated chains of 6 to 200 links (models/big/generate.py) and the
38-joint tree, timed by build/bench/dynamics_bench (CPU time, medians of 5 repetitions).
Writes docs/dynamics_scaling.csv and docs/dynamics_scaling.png (docs/performance.md).

  scripts/dynamics_scaling.py [--bench build/bench/dynamics_bench] [--plot-only]
"""
import argparse
import csv
import json
import os
import subprocess
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHAINS = [6, 12, 25, 50, 100, 150, 200]
ALGORITHMS = {"BM_InverseDynamics": "RNEA", "BM_ForwardDynamics": "ABA",
              "BM_MassMatrix": "CRBA"}


def measure(bench, out_csv):
    with tempfile.TemporaryDirectory() as tmp:
        urdfs = []
        for n in CHAINS:
            path = os.path.join(tmp, f"chain{n}.urdf")
            with open(path, "w") as f:
                subprocess.run([os.path.join(ROOT, "models/big/generate.py"), "chain", str(n)],
                               stdout=f, check=True)
            urdfs.append(path)
        urdfs.append(os.path.join(ROOT, "models/big/tree38.urdf"))
        result = subprocess.run(
            ["taskset", "-c", "1", bench] + [f"--urdf={u}" for u in urdfs] +
            ["--benchmark_filter=InverseDynamics|ForwardDynamics|MassMatrix",
             "--benchmark_min_time=0.1", "--benchmark_repetitions=5",
             "--benchmark_report_aggregates_only", "--benchmark_format=json"],
            check=True, capture_output=True, text=True)
    rows = []
    for b in json.loads(result.stdout)["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        name, robot = b["run_name"].split("/")
        joints = 38 if robot == "tree38" else int(robot.removeprefix("chain"))
        rows.append({"algorithm": ALGORITHMS[name], "robot": robot, "joints": joints,
                     "cpu_ns": round(b["cpu_time"], 1)})
    with open(out_csv, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=["algorithm", "robot", "joints", "cpu_ns"])
        writer.writeheader()
        writer.writerows(rows)


def plot(in_csv, out_png):
    rows = list(csv.DictReader(open(in_csv)))
    fig, (ax, per) = plt.subplots(1, 2, figsize=(11, 4.5))
    for algorithm, color in (("RNEA", "tab:blue"), ("ABA", "tab:red"), ("CRBA", "tab:grey")):
        chain = sorted((int(r["joints"]), float(r["cpu_ns"]) / 1000) for r in rows
                       if r["algorithm"] == algorithm and r["robot"].startswith("chain"))
        tree = [(int(r["joints"]), float(r["cpu_ns"]) / 1000) for r in rows
                if r["algorithm"] == algorithm and r["robot"] == "tree38"]
        ax.plot(*zip(*chain), "-o", color=color, label=f"{algorithm}, chain")
        ax.plot(*zip(*tree), "*", color=color, markersize=12, label=f"{algorithm}, 38-joint tree")
        per.plot([n for n, _ in chain], [1000 * t / n for n, t in chain], "-o", color=color,
                 label=algorithm)
    ax.set(xlabel="joints", ylabel="CPU time per call (µs)", title="time per call")
    per.set(xlabel="joints", ylabel="CPU time per call and joint (ns)",
            title="per joint (flat = linear cost)", ylim=(0, None))
    for a in (ax, per):
        a.grid(True, alpha=0.3)
        a.legend()
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--bench", default=os.path.join(ROOT, "build/bench/dynamics_bench"))
    parser.add_argument("--csv", default=os.path.join(ROOT, "docs/dynamics_scaling.csv"))
    parser.add_argument("--out", default=os.path.join(ROOT, "docs/dynamics_scaling.png"))
    parser.add_argument("--plot-only", action="store_true", help="plot the existing CSV")
    args = parser.parse_args()
    if not args.plot_only:
        measure(args.bench, args.csv)
    plot(args.csv, args.out)


if __name__ == "__main__":
    main()
