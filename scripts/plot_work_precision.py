#!/usr/bin/python3
"""Work-precision charts from the CSV of bench/work_precision.

    /usr/bin/python3 scripts/plot_work_precision.py --csv docs/work_precision.csv --out-dir docs

Writes one PNG per scene, <out-dir>/work_precision_<scene>.png: error (m) against CPU time
(s) on log-log axes, one line per formulation/method (points ordered by tolerance or step).
The body-coordinate formulations (body-index3, body-index2, body-baumgarte) are dash-dotted.
Runs that did not finish are red crosses at their CPU time on the top edge of the axes;
runs the study refused (status REFUSED: a formulation that does not take the scene) are not
drawn but named in the legend; runs with zero error (the closed form) sit on the bottom edge, labelled; the reference
row's agreement is a dashed line, the floor below which errors are not resolved. For
passive-swing a second panel shows the relative energy error, the long-time accuracy
figure of a scene whose TCP track is chaotic.
"""

import argparse
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402  (after the backend is chosen)

MACHINE = "2-core VM"
# The closed-loop linkages (models/linkages/): their error is the largest joint difference
# from the reference (rad; m for the slider), not the TCP's.
LINKAGES = {"four_bar", "slider_crank", "delta", "palletiser"}

# Fixed colours and markers per method, so the charts of different scenes match.
STYLES = {
    "none": ("black", "*"),
    "bdf": ("tab:blue", "o"),
    "adams": ("tab:cyan", "v"),
    "erk": ("tab:orange", "s"),
    "erk-verner": ("tab:brown", "D"),
    "dirk": ("tab:green", "^"),
    "rk4": ("tab:purple", "P"),
    "euler": ("tab:pink", "X"),
    "ida": ("darkgoldenrod", "<"),  # the joint space's GGL DAE (closed loops)
}
# The body-coordinate formulations, by formulation/method; dash-dotted lines.
BODY_STYLES = {
    "body-index3/ida": ("tab:red", "h"),
    "body-index2/ida": ("tab:olive", "p"),
    "body-baumgarte/bdf": ("tab:gray", "8"),
}


def style(formulation, method):
    """(colour, marker, linestyle) of a series."""
    key = f"{formulation}/{method}"
    if key in BODY_STYLES:
        return BODY_STYLES[key] + ("-.",)
    color, marker = STYLES.get(method, ("gray", "."))
    return color, marker, "--" if formulation == "kinematic" else "-"
FINISHED = "FINISHED"
# Rows with no run behind them: SKIPPED (tighter tolerances after a failure), REFERENCE (the
# reference run's own row) and REFUSED (the formulation does not take the scene; cpu_s is 0).
NOT_RUN = {"SKIPPED", "REFERENCE", "REFUSED"}


def read_rows(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    required = {"scene", "formulation", "method", "rtol", "step", "error", "cpu_s", "steps",
                "rhs_evals", "status"}
    if rows and not required.issubset(rows[0].keys()):
        sys.exit(f"{path}: missing columns {sorted(required - set(rows[0].keys()))}")
    for row in rows:
        for key in ("error", "cpu_s", "energy_error", "error_until", "t_reached"):
            value = row.get(key, "")
            row[key] = float(value) if value not in ("", None) else math.nan
        for key in ("rtol", "step"):
            row[key] = float(row[key]) if row[key] else None
        row["steps"] = int(row["steps"])
    return rows


def series_label(formulation, method, rows):
    if method == "none":
        return f"{formulation} (closed form)"
    kind = "step" if rows[0]["step"] is not None else "rtol"
    return f"{formulation} / {method} ({kind})"


def sweep_key(row):
    # Loosest first: large rtol or large step.
    value = row["rtol"] if row["rtol"] is not None else row["step"]
    return -(value if value is not None else 0.0)


def plot_panel(ax, groups, value_key, ylabel, reference=None, unit="m"):
    """Plots one log-log panel; returns nothing. groups: {(formulation, method): rows}."""
    finite = [r[value_key] for rows in groups.values() for r in rows
              if r["status"] == FINISHED and r[value_key] > 0 and math.isfinite(r[value_key])]
    cpus = [r["cpu_s"] for rows in groups.values() for r in rows
            if r["status"] not in NOT_RUN and r["cpu_s"] > 0]
    refused = [series_label(*key, rows) for key, rows in groups.items()
               if any(r["status"] == "REFUSED" for r in rows)]
    if not finite or not cpus:
        text = "\n".join(["no finished runs"] + [f"{label}: refused" for label in refused])
        ax.text(0.5, 0.5, text, transform=ax.transAxes, ha="center")
        return
    y_low = min(finite + ([reference] if reference else [])) / 10.0
    y_high = max(finite) * 30.0
    x_low, x_high = min(cpus) / 2.0, max(cpus) * 2.0
    failed_label_done = False
    failed_row = 0  # each method's failures on their own row along the top edge
    for (formulation, method), rows in groups.items():
        color, marker, linestyle = style(formulation, method)
        ok = [r for r in rows if r["status"] == FINISHED]
        # A failed run that took no measurable time sits at the left edge.
        bad = [dict(r, cpu_s=max(r["cpu_s"], x_low)) for r in rows
               if r["status"] not in NOT_RUN and r["status"] != FINISHED]
        label = series_label(formulation, method, rows)
        xs = [r["cpu_s"] for r in ok]
        ys = [r[value_key] if r[value_key] > 0 else y_low for r in ok]
        if ok:
            ax.plot(xs, ys, linestyle=linestyle, marker=marker, color=color, label=label,
                    markersize=5, linewidth=1.2)
            for r, y in zip(ok, ys):
                if r[value_key] == 0:
                    ax.annotate(f"{label}: error 0 (exact)", (r["cpu_s"], y),
                                textcoords="offset points", xytext=(6, 6), fontsize=7)
        elif bad:
            ax.plot([], [], linestyle=linestyle, marker=marker, color=color,
                    label=label + " - no run finished")
        if bad:
            y_fail = y_high * 2.5**failed_row
            failed_row += 1
            # The method's marker under the cross says whose failure it is.
            ax.plot([r["cpu_s"] for r in bad], [y_fail] * len(bad), linestyle="none",
                    marker=marker, color=color, markersize=7, alpha=0.5)
            ax.plot([r["cpu_s"] for r in bad], [y_fail] * len(bad), linestyle="none",
                    marker="x", color="red", markersize=8, markeredgewidth=1.5,
                    label=None if failed_label_done else "did not finish (at its CPU time)")
            failed_label_done = True
            name = method if formulation in ("joint", "kinematic") else f"{formulation}/{method}"
            text = f"{name}: {len(bad)} x {'/'.join(sorted({r['status'] for r in bad}))}"
            reached = max(r["t_reached"] for r in bad)
            if reached > 0:
                text += f", at best to t = {reached:.3g} s"
            skipped = sum(r["status"] == "SKIPPED" for r in rows)
            if skipped:
                text += f" (+{skipped} tighter rtol not run)"
            # Text to the right of the crosses, or to their left near the right edge.
            # (beside the leftmost cross when that is in the left half, so the text stays
            # inside the axes even when the crosses span the whole width).
            right = math.log(min(r["cpu_s"] for r in bad)) < 0.5 * (
                math.log(x_low) + math.log(x_high))
            ax.annotate(text, ((min if right else max)(r["cpu_s"] for r in bad), y_fail),
                        textcoords="offset points", xytext=(8 if right else -8, -3),
                        ha="left" if right else "right", fontsize=7, color="red")
    for label in refused:
        ax.plot([], [], linestyle="none", marker="", label=f"{label}: refused (not run)")
    if reference:
        ax.axhline(reference, color="gray", linestyle=":", linewidth=1.0,
                   label=f"reference agreement ({reference:.1g} {unit})")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(x_low, x_high)
    ax.set_ylim(y_low / 2.0, y_high * 2.5**max(failed_row, 1) * 1.5)
    ax.set_xlabel("CPU time of the run (s)")
    ax.set_ylabel(ylabel)
    ax.grid(True, which="major", linewidth=0.5, alpha=0.6)
    ax.grid(True, which="minor", linewidth=0.3, alpha=0.3)


def error_label(scene, rows):
    if scene == "seed-run":
        return "max TCP error vs closed form (m)"
    if scene in LINKAGES:
        return "max joint error vs reference (rad; m for a slider)"
    until = [r["error_until"] for r in rows if r["status"] == "REFERENCE"]
    durations = [r["t_reached"] for r in rows if r["status"] == FINISHED]
    if until and durations and until[0] < max(durations) - 1e-9:
        return f"max TCP error vs reference, t in [0, {until[0]:g}] s (m)"
    return "max TCP error vs reference (m)"


def plot_scene(scene, rows, out_dir):
    groups = {}
    for row in rows:
        if row["status"] == "REFERENCE":
            continue
        groups.setdefault((row["formulation"], row["method"]), []).append(row)
    for key in groups:
        groups[key].sort(key=sweep_key)
    reference = [r["error"] for r in rows if r["status"] == "REFERENCE"]
    reference = reference[0] if reference and reference[0] > 0 else None
    energy = scene == "passive-swing" and any(
        r["energy_error"] > 0 for r in rows if r["status"] == FINISHED)

    if energy:
        fig, axes = plt.subplots(1, 2, figsize=(17, 6.5))
    else:
        fig, axes = plt.subplots(1, 1, figsize=(12, 6.5))
        axes = [axes]
    plot_panel(axes[0], groups, "error", error_label(scene, rows), reference,
               "rad" if scene in LINKAGES else "m")
    axes[0].set_title("joint error" if scene in LINKAGES else "TCP error", fontsize=10)
    if energy:
        plot_panel(axes[1], groups, "energy_error", "max relative energy error")
        axes[1].set_title("energy balance error (no damping: energy should be constant)",
                          fontsize=10)
    handles, labels = axes[0].get_legend_handles_labels()
    axes[-1].legend(handles, labels, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    durations = [r["t_reached"] for r in rows if r["status"] == FINISHED]
    duration = f", {max(durations):g} s simulated" if durations else ""
    model = "closed-loop linkage" if scene in LINKAGES else "IRB 1600"
    fig.suptitle(f"Work-precision: {scene}{duration} ({model}; {MACHINE})", fontsize=12)
    fig.tight_layout()
    path = os.path.join(out_dir, f"work_precision_{scene}.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--csv", required=True, help="the CSV written by work_precision")
    parser.add_argument("--out-dir", required=True, help="where to write the PNGs")
    args = parser.parse_args()
    rows = read_rows(args.csv)
    if not rows:
        sys.exit(f"{args.csv}: no rows")
    os.makedirs(args.out_dir, exist_ok=True)
    scenes = []
    for row in rows:
        if row["scene"] not in scenes:
            scenes.append(row["scene"])
    for scene in scenes:
        path = plot_scene(scene, [r for r in rows if r["scene"] == scene], args.out_dir)
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
