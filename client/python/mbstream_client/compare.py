"""Two runs side by side on their common time grid, as the viewer's --compare shows them:
the same rule as the server's (server/runs/replay_grid.cc): both runs' frames lie at
k * interval from t = 0; one interval must be a whole multiple of the other (within 1e-9
relative); the grid is the coarser interval over the shorter run."""
from dataclasses import dataclass

import numpy as np

from .result import Result


@dataclass
class Comparison:
    """t (K,): s, the common times; tcp, ghost_tcp (K, 3): m, both runs' TCPs there;
    distance (K,): m, |tcp - ghost_tcp|; max_distance: m, its maximum; stride and
    ghost_stride: frames of each run per grid step."""
    run_id: str
    ghost_run_id: str
    t: np.ndarray
    tcp: np.ndarray
    ghost_tcp: np.ndarray
    distance: np.ndarray
    max_distance: float
    stride: int
    ghost_stride: int


def _interval(result: Result) -> float:
    return float(result.t[1] - result.t[0]) if len(result.t) > 1 else 0.0


def _whole_ratio(coarse: float, fine: float) -> int:
    if not fine > 0.0 or not coarse >= fine:
        return 0
    ratio = coarse / fine
    n = round(ratio)
    return int(n) if abs(ratio - n) <= 1e-9 * ratio else 0


def compare_results(run: Result, ghost: Result) -> Comparison:
    """The comparison of `run` with `ghost` (ValueError naming both runs and what to do when
    their joints differ or their grids cannot be aligned)."""
    both = "cannot compare run %s with run %s: " % (run.run_id, ghost.run_id)
    if run.joint_names != ghost.joint_names:
        raise ValueError(both + "their models' joints differ (%s against %s)"
                         % (",".join(run.joint_names), ",".join(ghost.joint_names)))
    if len(run.t) == 0 or len(ghost.t) == 0:
        raise ValueError(both + "a run has no stored frames")
    stride, ghost_stride = 1, 1
    if len(run.t) > 1 and len(ghost.t) > 1:
        a, b = _interval(run), _interval(ghost)
        n = _whole_ratio(max(a, b), min(a, b))
        if n == 0:
            raise ValueError(both + "their time grids cannot be aligned (a frame every %.9g s "
                             "against every %.9g s)" % (a, b))
        if a <= b:
            stride = n
        else:
            ghost_stride = n
    k = min((len(run.t) - 1) // stride, (len(ghost.t) - 1) // ghost_stride) + 1
    rows, ghost_rows = np.arange(k) * stride, np.arange(k) * ghost_stride
    if k > 1 and abs(run.t[rows[-1]] - ghost.t[ghost_rows[-1]]) > 1e-9 * max(
            1.0, abs(run.t[rows[-1]])):
        rows, ghost_rows = rows[:-1], ghost_rows[:-1]  # an extra frame at the end time
    tcp, ghost_tcp = run.tcp[rows], ghost.tcp[ghost_rows]
    distance = np.sqrt(np.sum((tcp - ghost_tcp) ** 2, axis=1))
    return Comparison(run.run_id, ghost.run_id, run.t[rows], tcp, ghost_tcp, distance,
                      float(distance.max()) if len(distance) else 0.0, stride, ghost_stride)
