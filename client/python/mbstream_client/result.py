"""A run's stored result as NumPy arrays, with joint names, a pandas view and plots."""
import os
from dataclasses import dataclass, field
from typing import Any, Dict, Iterable, List, Optional, Union

import numpy as np
from google.protobuf import json_format

from ._stubs import run_pb2
from .mcap import StartLike, save_mcap


def stats_dict(info: "run_pb2.RunInfo") -> Dict[str, Any]:
    """RunStats of a RunInfo as a dict (every field, defaults included) plus the run's
    `state` and `message`, like the results directory's stats.json."""
    try:
        stats = json_format.MessageToDict(info.stats, preserving_proto_field_name=True,
                                          including_default_value_fields=True)
    except TypeError:  # protobuf >= 5 renamed the option
        stats = json_format.MessageToDict(info.stats, preserving_proto_field_name=True,
                                          always_print_fields_with_no_presence=True)
    for key in ("steps", "rhs_evals", "jac_evals", "nonlinear_iterations",
                "error_test_failures", "convergence_failures", "max_steps"):
        stats[key] = int(stats.get(key, 0))  # the JSON mapping writes int64 as strings
    summary = stats.get("summary") or {}
    for key in ("frames_computed", "frames_kept"):
        if key in summary:
            summary[key] = int(summary[key])
    stats["state"] = run_pb2.RunState.Name(info.state)
    stats["message"] = info.message
    return stats


PROBE_FIELDS = ("seq", "t", "name", "x", "y", "z", "frame", "latency_us")


QUANTITIES = {  # name: (attribute, unit, what)
    "q": ("q", "rad | m", "joint positions"),
    "qd": ("qd", "rad/s | m/s", "joint velocities"),
    "tau": ("tau", "N*m | N", "drive efforts"),
}


@dataclass
class Result:
    """The result of one run. Arrays have one row per output frame: N frames, n joints in the
    model's joint order (`joint_names[j]` names column j), SI units. A model with free bodies
    or ball joints has more position coordinates than velocities (docs/free_bodies.md): q's
    columns are then named by position_names (a free joint NAME's NAME.x .y .z .qw .qx .qy
    .qz), qd's and tau's by joint_names (NAME.vx .vy .vz .wx .wy .wz).

    t (N,):           s, simulated time of each frame
    q (N, nq):        rad (revolute) or m (prismatic), joint positions; m and a unit
                      quaternion for a free body; nq = n without free bodies and ball joints
    qd (N, n):        rad/s or m/s, joint velocities
    tau (N, n):       N*m or N, drive efforts; (N, 0) when the run computed no torques
    tcp (N, 3):       m, x y z of the TCP in the model's base (world) frame
    kinetic, potential (N,): J (zeros unless info.has_energy)
    seq (N,):         the frames' sequence numbers (frame k is at k * output interval)
    probes:           a structured array, one row per probe report a viewer sent: seq, t (s),
                      name, x y z (m, in `frame`), frame, latency_us (empty without a viewer)
    stats:            the run's statistics (like stats.json) plus its state and message
    info:             the RunInfo message
    loop_forces (N, 6 c): a mechanism with closed loops run with spec report_loop_forces: per
                      cut joint (loop_force_names) the force (N) and torque (N*m, about the
                      joint's origin) its parent side exerts on its child side, world frame,
                      like loop_forces.csv; (N, 0) otherwise

    to_pandas() gives the same as DataFrames indexed by t (pandas, optional); plot_tcp() and
    plot_joints() draw them with matplotlib (for a notebook); to_mcap(path) writes the run as
    an MCAP file for ROS 2 tools and Foxglove."""
    run_id: str
    model_id: str
    model_name: str
    state: str
    message: str
    joint_names: List[str]
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    tcp: np.ndarray
    tau: np.ndarray
    kinetic: np.ndarray
    potential: np.ndarray
    seq: np.ndarray
    probes: np.ndarray
    stats: Dict[str, Any]
    info: "run_pb2.RunInfo" = field(repr=False)
    loop_force_names: List[str] = field(default_factory=list)
    # q's column names: joint_names for a model without free bodies or ball joints.
    position_names: List[str] = field(default_factory=list)
    loop_forces: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)), repr=False)
    # The server it came from (a SimulationStub) and its probe set, for to_mcap.
    _stub: Any = field(default=None, repr=False, compare=False)
    _probe_set: str = field(default="", repr=False, compare=False)

    @property
    def finished(self) -> bool:
        """The run reached its end time."""
        return self.state == "FINISHED"

    @property
    def server_version(self) -> str:
        """The mbstream version of the server that computed the run (RunInfo.mbstream_version;
        compare with mbstream_client.__version__ for reproducibility)."""
        return self.info.mbstream_version

    @property
    def probe_names(self) -> List[str]:
        """The names of the probes that reported, sorted."""
        return sorted(set(self.probes["name"].tolist()))

    def joint(self, name: str) -> int:
        """The column of velocity coordinate `name` in qd and tau (and in q when the model
        has no free bodies or ball joints; else see position)."""
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise KeyError("run %s has no joint '%s'; its joints: %s"
                           % (self.run_id, name, ", ".join(self.joint_names))) from None

    def position(self, name: str) -> int:
        """The column of position coordinate `name` in q (a one-coordinate joint by its
        name, a free joint's by NAME.x ... NAME.qz)."""
        names = self.position_names or self.joint_names
        try:
            return names.index(name)
        except ValueError:
            raise KeyError("run %s has no position coordinate '%s'; its coordinates: %s"
                           % (self.run_id, name, ", ".join(names))) from None

    def to_mcap(self, path: Union[str, "os.PathLike[str]"], compression: str = "zstd",
                start: StartLike = None) -> str:
        """Writes the run as one MCAP file at `path` (rosbag2's format: `ros2 bag info`,
        Foxglove and PlotJuggler open it; docs/mcap.md): /joint_states
        (sensor_msgs/msg/JointState), /tf and /tf_static (each link's pose in its parent),
        /robot_description (the URDF), /mbstream/probes (this result's probe reports) and
        /mbstream/stats. The server that computed the run writes the file (it has the model)
        and its bytes are saved as they come, written as path + ".tmp" and renamed once whole.
        compression: each chunk's, "zstd", "lz4" or "none". start: the UTC time of t = 0 in
        the stamps: None (the run's start), "2026-11-26T12:00:00Z", seconds since the Unix
        epoch, or a datetime (naive = UTC). Returns `path`."""
        if self._stub is None:
            raise ValueError("result of run %s was not fetched from a server (Run.result, "
                             "Client.result or Client.results); use "
                             "Client.export_mcap(run_id, path)" % self.run_id)
        save_mcap(self._stub, self.run_id, path, compression, start, self._probe_set)
        return os.fspath(path)

    def to_pandas(self, quantity: Optional[str] = None) -> Any:
        """The result as a pandas DataFrame indexed by t (s). quantity "q", "qd" or "tau":
        one column per joint, named by the joint (like joints.csv); "tcp": columns x y z (m,
        base frame); "energy": kinetic, potential (J); None: all of them side by side, with
        two-level columns (quantity, name), e.g. df["q"]["joint_1"]. Needs pandas (an
        optional dependency: apt-get install python3-pandas)."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Result.to_pandas needs pandas (Debian: apt-get install "
                              "python3-pandas)") from None
        index = pd.Index(self.t, name="t")
        tables = {
            "q": (self.q, self.position_names or self.joint_names),
            "qd": (self.qd, self.joint_names),
            "tau": (self.tau, self.joint_names if self.tau.shape[1] else []),
            "tcp": (self.tcp, ["x", "y", "z"]),
            "energy": (np.column_stack([self.kinetic, self.potential]),
                       ["kinetic", "potential"]),
        }
        if quantity is not None:
            if quantity not in tables:
                raise ValueError("quantity must be one of %s, not %r"
                                 % (", ".join(tables), quantity))
            values, columns = tables[quantity]
            return pd.DataFrame(values, index=index, columns=list(columns))
        frames = {name: pd.DataFrame(values, index=index, columns=list(columns))
                  for name, (values, columns) in tables.items() if len(columns)}
        return pd.concat(frames, axis=1)

    def plot_tcp(self, ax: Any = None, label: Optional[str] = None) -> Any:
        """Plots the TCP's x, y, z (m, base frame) against t (s) with matplotlib, on `ax`
        (a new figure's axes when None); returns the axes."""
        plt = _pyplot()
        if ax is None:
            _, ax = plt.subplots(figsize=(7, 4))
        for k, axis in enumerate("xyz"):
            ax.plot(self.t, self.tcp[:, k], label="%s%s" % (label + " " if label else "", axis))
        ax.set_xlabel("t (s)")
        ax.set_ylabel("TCP position (m, base frame)")
        ax.set_title("run %s (%s): TCP" % (self.run_id, self.model_name), fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        return ax

    def plot_joints(self, quantity: str = "q", joints: Optional[Iterable[str]] = None,
                    ax: Any = None) -> Any:
        """Plots one quantity ("q", "qd" or "tau") of the joints named in `joints` (all when
        None) against t (s), one line per joint labelled by its name; returns the axes."""
        if quantity not in QUANTITIES:
            raise ValueError("quantity must be one of %s, not %r"
                             % (", ".join(QUANTITIES), quantity))
        attribute, unit, what = QUANTITIES[quantity]
        values = getattr(self, attribute)
        if values.shape[1] == 0:
            raise ValueError("run %s has no %s (the run computed none)" % (self.run_id, what))
        plt = _pyplot()
        if ax is None:
            _, ax = plt.subplots(figsize=(7, 4))
        by_position = quantity == "q" and bool(self.position_names)
        names = self.position_names if by_position else self.joint_names
        column = self.position if by_position else self.joint
        for name in (names if joints is None else list(joints)):
            ax.plot(self.t, values[:, column(name)], label=name)
        ax.set_xlabel("t (s)")
        ax.set_ylabel("%s (%s)" % (quantity, unit))
        ax.set_title("run %s (%s): %s" % (self.run_id, self.model_name, what), fontsize=10)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        return ax

    def probe(self, name: Optional[str] = None) -> np.ndarray:
        """The reports of one probe (the only one when `name` is None), in frame order."""
        if name is None:
            names = self.probe_names
            if len(names) != 1:
                raise ValueError("run %s has probes %s; name one" % (self.run_id, names))
            name = names[0]
        rows = self.probes[self.probes["name"] == name]
        return rows[np.argsort(rows["seq"], kind="stable")]


def _pyplot() -> Any:
    try:
        import matplotlib.pyplot as plt
    except ImportError:
        raise ImportError("plotting needs matplotlib (Debian: apt-get install "
                          "python3-matplotlib)") from None
    return plt


def _tail(frames: List[Any], attribute: str, width: int) -> np.ndarray:
    """The last `width` of each frame's `attribute` values."""
    if not frames or width == 0:
        return np.zeros((len(frames), width))
    return np.array([list(getattr(f, attribute))[-width:] for f in frames], dtype=float)


def _matrix(frames: List[Any], attribute: str, width: int, extra: int = 0) -> np.ndarray:
    """The first `width` of each frame's `attribute` values, which has `extra` more."""
    if not frames or width == 0:
        return np.zeros((len(frames), width))
    values = np.array([list(getattr(f, attribute)) for f in frames], dtype=float)
    return values.reshape(len(frames), width + extra)[:, :width]


def result_from_chunks(chunks: Iterable["run_pb2.ResultChunk"], stub: Any = None,
                       probe_set: str = "") -> Result:
    """A Result from GetResult's stream of ResultChunk messages (`stub`: the server's
    SimulationStub they came from, for Result.to_mcap; `probe_set`: the one asked for)."""
    info = None
    frames, probes = [], []
    for chunk in chunks:
        if chunk.HasField("info"):
            info = chunk.info
        frames.extend(chunk.frames)
        probes.extend(chunk.probes)
    if info is None:
        info = run_pb2.RunInfo()
    n = info.num_dofs or (len(frames[0].q) if frames else 0)
    nq = info.num_positions or n
    # Frame.tau: the drive efforts (n, or none), then the cut joints' reactions (6 each) of a
    # run with closed loops and spec.report_loop_forces.
    cut_joints = [c[:c.rfind(" (")] if " (" in c else c for c in info.stats.loops.cut_joints]
    loop_force_names = cut_joints if info.spec.report_loop_forces else []
    reactions = 6 * len(loop_force_names)
    has_tau = bool(frames) and len(frames[0].tau) == n + reactions and n > 0
    names = [p.probe for p in probes]
    frame_names = [p.frame for p in probes]
    dtype = [("seq", "i8"), ("t", "f8"), ("name", "U%d" % max([1] + [len(s) for s in names])),
             ("x", "f8"), ("y", "f8"), ("z", "f8"),
             ("frame", "U%d" % max([1] + [len(s) for s in frame_names])), ("latency_us", "i8")]
    probe_rows = np.array(
        [(p.seq, p.t_s, p.probe, p.position_m.x, p.position_m.y, p.position_m.z, p.frame,
          p.latency_us) for p in probes], dtype=dtype)
    return Result(
        run_id=info.id, model_id=info.model_id, model_name=info.model_name,
        state=run_pb2.RunState.Name(info.state), message=info.message,
        joint_names=list(info.joint_names),
        t=np.array([f.t_s for f in frames], dtype=float),
        q=_matrix(frames, "q", nq), qd=_matrix(frames, "qd", n),
        tcp=np.array([(f.tcp_m.x, f.tcp_m.y, f.tcp_m.z) for f in frames],
                     dtype=float).reshape(len(frames), 3),
        tau=_matrix(frames, "tau", n if has_tau else 0, reactions),
        kinetic=np.array([f.kinetic_j for f in frames], dtype=float),
        potential=np.array([f.potential_j for f in frames], dtype=float),
        seq=np.array([f.seq for f in frames], dtype=np.int64),
        probes=probe_rows, stats=stats_dict(info), info=info, loop_force_names=loop_force_names,
        loop_forces=_tail(frames, "tau", reactions), position_names=list(info.position_names),
        _stub=stub, _probe_set=probe_set)
