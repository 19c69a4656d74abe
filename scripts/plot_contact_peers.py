#!/usr/bin/python3
"""Contact beside MuJoCo: the chart of bench/contact_peers's CSV.

    /usr/bin/python3 scripts/plot_contact_peers.py --csv docs/contact_peers.csv --out docs

Writes <out>/contact_peers.png: one panel per scene (incline, rolling, bounce), the error
against the closed form (relative) over the CPU time per simulated second, log-log; one line
per engine and family of settings (mbstream: a surface stiffness, its tolerances; MuJoCo: a
solref, its timesteps), each engine's default setting ringed. A run whose error is 1 (no
bounce at all, MuJoCo's default inelastic contact) sits on the top edge.
"""

import argparse
import csv
import os
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)

MACHINE = "2-core VM"


def family(row):
    """The series a row belongs to: the engine and the settings that stay fixed."""
    setting = row["setting"]
    if row["engine"] == "mbstream":
        return "mbstream " + setting.split(";")[0]  # "mbstream k 1e5"
    match = re.match(r"solref ([^;]+);", setting)
    return "MuJoCo " + ("solref " + match.group(1) if match else "default solref")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--csv", required=True)
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    with open(args.csv, newline="") as f:
        rows = list(csv.DictReader(f))
    scenes = ["incline", "rolling", "bounce"]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8))
    colours = {}
    palette = ["tab:blue", "tab:cyan", "tab:orange", "tab:red"]
    for ax, scene in zip(axes, scenes):
        series = {}
        for row in rows:
            if row["scene"] == scene:
                series.setdefault(family(row), []).append(row)
        for name, points in series.items():
            colour = colours.setdefault(name, palette[len(colours) % len(palette)])
            xs = [float(p["cpu_per_sim_s"]) for p in points]
            ys = [max(float(p["error"]), 1e-9) for p in points]
            ax.plot(xs, ys, "o-", color=colour, label=name)
            for p, x, y in zip(points, xs, ys):
                if "(default)" in p["setting"]:
                    ax.plot([x], [y], "o", markersize=14, markerfacecolor="none",
                            markeredgecolor="black")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(scene)
        ax.set_xlabel("CPU s per simulated s")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    axes[0].set_ylabel("error against the closed form (relative)")
    fig.suptitle("Contact beside MuJoCo 2.2.2 (defaults ringed; " + MACHINE + ")")
    fig.tight_layout()
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "contact_peers.png")
    fig.savefig(path, dpi=110)
    print("wrote", path)


if __name__ == "__main__":
    main()
