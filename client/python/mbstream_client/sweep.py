"""A parameter sweep as one job: the server stores a base spec and a grid (or a list of
points) and feeds its runs itself, a window at a time (StartSweep); a client follows it
(GetSweep, GetResult) and gathers each run's summary into one table, the same columns as
`mbstream sweep`'s sweep.csv. Following is reading only: a client that stops (Ctrl-C, a
lost connection) leaves the sweep going, and Sweep(client, sweep_id).wait() picks it up
again from any client."""
import json
import sys
import time
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple

from ._stubs import run_pb2
from ._stubs import simulation_service_pb2 as service_pb2
from .errors import rpc_errors
from .result import Result


def _json_values(path: str, values: Iterable[Any]) -> List[str]:
    texts = []
    for value in values:
        if isinstance(value, bool) or isinstance(value, (int, float, str)):
            texts.append(json.dumps(value))
        elif hasattr(value, "item"):  # a NumPy scalar
            texts.append(json.dumps(value.item()))
        else:
            raise TypeError("sweep value of %s must be a number, a str or a bool, not %s"
                            % (path, type(value).__name__))
    if not texts:
        raise ValueError("sweep axis %s has no values; give at least one" % path)
    return texts


def sweep_request(model: str, base: Any, grid: Optional[Mapping[str, Iterable[Any]]],
                  points: Optional[Sequence[Mapping[str, Any]]]) -> Any:
    """The StartSweepRequest of a grid (path -> values) or a list of points (dicts)."""
    request = service_pb2.StartSweepRequest(model=model, base=base)
    if (grid is None) == (points is None):
        raise ValueError("give grid={path: values, ...} or points=[{path: value, ...}, ...], "
                         "one of the two")
    if grid is not None:
        for path, values in grid.items():
            request.grid.add(path=path, values=_json_values(path, values))
    else:
        assert points is not None
        paths = list(points[0].keys()) if points else []
        if not paths:
            raise ValueError("points is empty; give at least one point")
        request.list_paths.extend(paths)
        for k, point in enumerate(points):
            if list(point.keys()) != paths:
                raise ValueError("points[%d] has the paths %s; every point needs %s"
                                 % (k, list(point.keys()), paths))
            request.list.add(values=[_json_values(p, [point[p]])[0] for p in paths])
    return request


def _figure(value: float) -> Optional[float]:
    return None if value < 0 else value


def sweep_row(result: Result, paths: List[str], values: List[str]) -> Dict[str, Any]:
    """One run's row: its id, the swept values, then its summary (as sweep.csv)."""
    info, stats = result.info, result.info.stats
    row: Dict[str, Any] = {"run_id": info.id}
    for path, text in zip(paths, values):
        try:
            row[path] = json.loads(text)
        except ValueError:
            row[path] = text
    row.update(state=run_pb2.RunState.Name(info.state), trust=stats.trust,
               t_reached_s=stats.t_reached_s, frames_kept=info.frames, steps=stats.steps,
               cpu_s=stats.cpu_s, tcp_error_max_m=_figure(stats.tcp_error_max_m),
               energy_error_max=_figure(stats.energy_error_max),
               target_met=stats.target_met if stats.HasField("target_met") else None)
    summary = stats.summary
    for j, joint in enumerate(info.joint_names):
        figures = summary.joints[j] if j < len(summary.joints) else None
        row["tracking_error_max:" + joint] = _figure(figures.tracking_error_max) if figures else None
        row["effort_peak:" + joint] = _figure(figures.effort_peak) if figures else None
        row["effort_rms:" + joint] = _figure(figures.effort_rms) if figures else None
        row["q_final:" + joint] = summary.q_final[j] if j < len(summary.q_final) else None
    row["message"] = info.message
    return row


def progress_line(progress: Any) -> str:
    """A sweep's progress (SweepProgress) as one line with a bar, as `mbstream sweep` shows it:
    "sweep s-...: [#####.....] 12/24 runs ended (FINISHED 12), 2 running, 10 queued"."""
    total = max(progress.total_points, 1)
    width = 20
    done = width * progress.ended_runs // total
    ended, waiting = [], []
    for entry in progress.states:
        name = run_pb2.RunState.Name(entry.state)
        if name in ("QUEUED", "RUNNING"):
            waiting.append("%d %s" % (entry.runs, name.lower()))
        else:
            ended.append("%s %d" % (name, entry.runs))
    line = "sweep %s: [%s%s] %d/%d runs ended" % (progress.sweep_id, "#" * done,
                                                   "." * (width - done), progress.ended_runs,
                                                   progress.total_points)
    if ended:
        line += " (%s)" % ", ".join(ended)
    if waiting:
        line += ", " + ", ".join(waiting)
    if progress.total_points > progress.started_runs:
        line += ", %d not started" % (progress.total_points - progress.started_runs)
    return line + (" - cancelled" if progress.cancelled else "")


class _Progress:
    """The sweep's progress on stderr from GetSweep, at most twice a second (and at the end)."""

    def __init__(self, client: Any, shown: bool):
        self.client, self.shown, self.last = client, shown, 0.0
        self.terminal = shown and sys.stderr.isatty()

    def show(self, sweep_id: str, last: bool) -> None:
        now = time.monotonic()
        if not self.shown or (not last and now - self.last < 0.5):
            return
        self.last = now
        line = progress_line(self.client.sweep_progress(sweep_id))
        sys.stderr.write(("\r\033[K" + line + ("\n" if last else "")) if self.terminal
                         else line + "\n")
        sys.stderr.flush()


# Runs asked of GetSweep at a time while following.
_PAGE = 64


class Sweep:
    """A sweep on the server, by its id (Client.start_sweep, or Sweep(client, "s-...") for one
    started anywhere). The server feeds it whether or not anyone follows it."""

    def __init__(self, client: Any, sweep_id: str):
        self.client, self.id = client, sweep_id

    def __repr__(self) -> str:
        return "Sweep(%r)" % self.id

    def progress(self) -> Any:
        """Its progress as the server counts it (SweepProgress)."""
        return self.client.sweep_progress(self.id)

    def cancel(self) -> Any:
        """Cancels it (Client.cancel_sweep)."""
        return self.client.cancel_sweep(self.id)

    def rows(self, progress: bool = False) -> Tuple[List[Dict[str, Any]], bool]:
        """Follows it to its end: each run's row (sweep_row) in point order as the run ends,
        and whether it was cancelled (the points never queued then have no row)."""
        rows: List[Dict[str, Any]] = []
        shown = _Progress(self.client, progress)
        cancelled = False
        while True:
            with rpc_errors():
                page = self.client.stub.GetSweep(service_pb2.GetSweepRequest(
                    sweep_id=self.id, runs_from=len(rows), max_runs=_PAGE))
            cancelled = cancelled or page.cancelled
            if not page.run_ids:
                if cancelled or len(rows) >= page.total_points:
                    break
                time.sleep(0.1)  # the next point is not queued yet
                continue
            paths = list(page.paths)
            for run_id, point in zip(page.run_ids, page.points):
                result = self.client.result(run_id, wait=True)
                rows.append(sweep_row(result, paths, list(point.values)))
                shown.show(self.id, False)
            if len(rows) >= page.total_points:
                break
        shown.show(self.id, True)
        return rows, cancelled

    def wait(self, progress: bool = False) -> Any:
        """Follows it to its end and returns its table (as Client.sweep). Interrupted
        (Ctrl-C), it stops following; the sweep goes on on the server."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Sweep.wait needs pandas (Debian: apt-get install "
                              "python3-pandas)") from None
        rows, cancelled = self.rows(progress)
        table = pd.DataFrame(rows)
        table.attrs.update(sweep_id=self.id, cancelled=cancelled)
        return table


def start_sweep(client: Any, request: Any, window: int) -> Sweep:
    """Starts the sweep on the server (it queues at most `window` of its runs at a time)."""
    if window < 1:
        raise ValueError("window must be at least 1, not %r" % (window,))
    request.window = window
    with rpc_errors():
        response = client.stub.StartSweep(request)
    return Sweep(client, response.sweep_id)
