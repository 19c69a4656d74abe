#!/usr/bin/python3
"""Contact beside MuJoCo and DART: the chart of bench/contact_peers's CSV.

    /usr/bin/python3 scripts/plot_contact_peers.py --csv docs/contact_peers.csv --out docs

Writes <out>/contact_peers.png: one panel per scene (incline, rolling, bounce), the error
against the closed form (relative) over the CPU time per simulated second, log-log; one line
per engine and family of settings (mbstream: a surface stiffness, its tolerances; MuJoCo: a
solref, its timesteps; DART: a collision detector, its time steps), each engine's default
setting ringed. A run whose error is 1 (no bounce at all, MuJoCo's default inelastic contact)
sits on the top edge, one under 1e-13 (round-off) on the bottom one. A CSV without DART rows
(DART not installed) charts the other two.
"""

import argparse
import csv
import os
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)

MACHINE = "2-core VM"
# Errors below this (the slope fit's round-off: DART's sliding box, mbstream's at k 1e8) are
# drawn on it.
FLOOR = 1e-13


def family(row):
    """The series a row belongs to: the engine and the settings that stay fixed."""
    setting = row["setting"]
    if row["engine"] == "mbstream":
        return "mbstream " + setting.split(";")[0]  # "mbstream k 1e5", "mbstream k 1e6 d 20"
    if row["engine"] == "dart":
        return "DART " + setting.split(";")[0]  # "DART fcl mesh"
    match = re.match(r"solref ([^;]+);", setting)
    return "MuJoCo " + ("solref " + match.group(1) if match else "default solref")


# Each engine its hue, each family of its settings a shade of it.
PALETTES = {
    "mbstream": ["tab:blue", "tab:cyan", "tab:purple", "navy", "tab:pink"],
    "MuJoCo": ["tab:orange", "tab:red"],
    "DART": ["tab:green", "tab:olive"],
}


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
    engines = sorted({r["engine"] for r in rows})
    for ax, scene in zip(axes, scenes):
        series = {}
        for row in rows:
            if row["scene"] == scene:
                series.setdefault(family(row), []).append(row)
        for name, points in series.items():
            if name not in colours:
                engine = name.split(" ")[0]
                used = sum(1 for n in colours if n.split(" ")[0] == engine)
                shades = PALETTES[engine]
                colours[name] = shades[used % len(shades)]
            colour = colours[name]
            xs = [float(p["cpu_per_sim_s"]) for p in points]
            ys = [max(float(p["error"]), FLOOR) for p in points]
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
    peers = "MuJoCo 2.2.2 and DART 6.12" if "dart" in engines else "MuJoCo 2.2.2"
    fig.suptitle("Contact beside " + peers + " (defaults ringed; " + MACHINE + ")")
    fig.tight_layout()
    os.makedirs(args.out, exist_ok=True)
    path = os.path.join(args.out, "contact_peers.png")
    fig.savefig(path, dpi=110)
    print("wrote", path)


if __name__ == "__main__":
    main()
