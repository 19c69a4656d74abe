"""A parameter sweep as one job: the server expands a base spec and a grid (or a list of
points) into runs (StartSweep), and the client gathers each run's summary into one table,
the same columns as `mbstream sweep`'s sweep.csv."""
import json
import sys
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence

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


def run_sweep(client: Any, request: Any, window: int, progress: bool) -> List[Dict[str, Any]]:
    """Starts the sweep a window of runs at a time and returns its rows in point order."""
    if window < 1:
        raise ValueError("window must be at least 1, not %r" % (window,))
    pending: List[Any] = []
    rows: List[Dict[str, Any]] = []
    paths: List[str] = []
    total = 0

    def start(count: int) -> None:
        nonlocal total, paths
        request.max_runs = count
        with rpc_errors():
            response = client.stub.StartSweep(request)
        request.sweep_id, request.first_point = response.sweep_id, response.next_point
        total, paths = response.total_points, list(response.paths)
        pending.extend(zip([r.id for r in response.runs], [list(p.values) for p in response.points]))

    start(window)
    while pending:
        run_id, values = pending.pop(0)
        result = client.result(run_id, wait=True)
        rows.append(sweep_row(result, paths, values))
        if progress:
            sys.stderr.write("sweep %s: %d/%d runs ended\n" % (request.sweep_id, len(rows), total))
        room = window - len(pending)
        if request.first_point < total and room >= max(1, window // 2):
            start(room)
    return rows
