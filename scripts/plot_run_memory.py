#!/usr/bin/python3
"""Plots docs/run_memory.csv (from bench/run_memory): peak RSS of mbstream-server against a
run's frames, before and after frames were streamed to the store."""
import argparse
import csv

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--csv", default="docs/run_memory.csv")
    parser.add_argument("--out", default="docs/run_memory.png")
    args = parser.parse_args()
    rows = list(csv.DictReader(open(args.csv)))
    fig, ax = plt.subplots(figsize=(7, 4.5))
    styles = {"before": ("tab:red", "o"), "after": ("tab:blue", "s")}
    for server, (color, marker) in styles.items():
        mine = [r for r in rows if r["server"] == server]
        frames = [int(r["frames"]) for r in mine]
        for column, line, label in (("run_peak_mb", "-", "peak during the run"),
                                    ("result_peak_mb", "--", "peak during GetResult"),
                                    ("after_result_mb", ":", "resident when idle again")):
            ax.plot(frames, [float(r[column]) for r in mine], line, color=color, marker=marker,
                    label=f"{server}: {label}")
    idle = [float(r["idle_mb"]) for r in rows]
    ax.axhline(sum(idle) / len(idle), color="grey", linewidth=0.8, label="idle (warmed up)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("frames of the run (seed experiment, 6 joints)")
    ax.set_ylabel("RSS of mbstream-server, MB (VmHWM / VmRSS)")
    ax.set_title("Memory of one run against its length")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)


if __name__ == "__main__":
    main()
