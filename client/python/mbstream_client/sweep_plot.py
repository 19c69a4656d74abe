"""A chart of a sweep's table (Client.sweep's DataFrame, or sweep.csv read with pandas): one
summary metric over two swept paths as a heat map, e.g. the tracking error against kp and kd.

    table = server.sweep("irb1600", "models/irb1600/seed-servo.json", duration=2,
                         grid={"drives[1].pd_servo.kp": [400, 800, 1600, 3200],
                               "drives[1].pd_servo.kd": [20, 40, 80]})
    mb.plot_sweep(table, "drives[1].pd_servo.kp", "drives[1].pd_servo.kd",
                  "tracking_error_max:joint2", path="sweep.png")
"""
import math
from typing import Any, List, Optional

import numpy as np

from .result import _pyplot


def _axis_values(table: Any, column: str) -> List[Any]:
    if column not in table.columns:
        raise ValueError("the sweep's table has no column %r; its columns: %s"
                         % (column, ", ".join(str(c) for c in table.columns)))
    return sorted(table[column].dropna().unique().tolist())


def _label(value: Any) -> str:
    return "%g" % value if isinstance(value, float) else str(value)


def plot_sweep(table: Any, x: str, y: str, value: str, ax: Any = None,
               path: Optional[str] = None, annotate: Optional[bool] = None,
               cmap: str = "viridis") -> Any:
    """Plots `value` (a column of the table, e.g. "tracking_error_max:joint2") as a heat map
    over the swept paths `x` (columns) and `y` (rows), each axis in ascending order of its
    values; a cell with several runs shows their mean, one with none (or a run that did not
    finish: its metric is empty) stays blank. On `ax` (a new figure's when None); with `path`
    the figure is saved there (PNG by its extension). `annotate`: write each cell's value
    (default: when the grid has at most 12 x 12 cells). Returns the axes."""
    xs, ys = _axis_values(table, x), _axis_values(table, y)
    if value not in table.columns:
        _axis_values(table, value)  # raises, naming the columns
    grid = np.full((len(ys), len(xs)), np.nan)
    numbers = table[[x, y, value]].copy()
    numbers[value] = numbers[value].astype(float)
    for (xv, yv), cell in numbers.groupby([x, y])[value]:
        mean = cell.mean()
        if not math.isnan(mean):
            grid[ys.index(yv), xs.index(xv)] = mean
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(1.2 + 0.9 * len(xs), 1.2 + 0.6 * len(ys)))
    image = ax.imshow(np.ma.masked_invalid(grid), origin="lower", aspect="auto", cmap=cmap)
    ax.set_xticks(range(len(xs)), [_label(v) for v in xs])
    ax.set_yticks(range(len(ys)), [_label(v) for v in ys])
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    ax.figure.colorbar(image, ax=ax, label=value)
    sweep_id = table.attrs.get("sweep_id", "") if hasattr(table, "attrs") else ""
    ax.set_title(("sweep %s: %s" % (sweep_id, value)) if sweep_id else value, fontsize=10)
    if annotate if annotate is not None else len(xs) <= 12 and len(ys) <= 12:
        middle = np.nanmean(grid) if np.isfinite(grid).any() else 0.0
        for row, column in zip(*np.nonzero(np.isfinite(grid))):
            cell = grid[row, column]
            ax.text(column, row, "%.3g" % cell, ha="center", va="center", fontsize=8,
                    color="black" if cell > middle else "white")
    if path is not None:
        ax.figure.savefig(path, dpi=100, bbox_inches="tight")
    return ax
