"""A run's stored result as NumPy arrays."""
from dataclasses import dataclass, field

import numpy as np
from google.protobuf import json_format

from ._stubs import run_pb2


def stats_dict(info):
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
    stats["state"] = run_pb2.RunState.Name(info.state)
    stats["message"] = info.message
    return stats


PROBE_FIELDS = ("seq", "t", "name", "x", "y", "z", "frame", "latency_us")


@dataclass
class Result:
    """The result of one run. Arrays have one row per output frame (N frames, n joints in
    the model's joint order, SI units: s, rad or m, rad/s or m/s, m, N*m or N, J).

    t (N,), q (N, n), qd (N, n), tcp (N, 3), tau (N, n) — (N, 0) when the run computed no
    torques —, kinetic and potential (N,) (zeros unless info.has_energy), seq (N,) the frames'
    sequence numbers; probes: a structured array with one row per probe report, fields seq,
    t, name, x, y, z, frame, latency_us (empty when no viewer answered); stats: a dict of
    the run's statistics plus its state and message; info: the RunInfo message."""
    run_id: str
    model_id: str
    model_name: str
    state: str
    message: str
    joint_names: list
    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    tcp: np.ndarray
    tau: np.ndarray
    kinetic: np.ndarray
    potential: np.ndarray
    seq: np.ndarray
    probes: np.ndarray
    stats: dict
    info: object = field(repr=False)

    @property
    def finished(self):
        """The run reached its end time."""
        return self.state == "FINISHED"

    @property
    def probe_names(self):
        return sorted(set(self.probes["name"].tolist()))

    def probe(self, name=None):
        """The reports of one probe (the only one when `name` is None), in frame order."""
        if name is None:
            names = self.probe_names
            if len(names) != 1:
                raise ValueError("run %s has probes %s; name one" % (self.run_id, names))
            name = names[0]
        rows = self.probes[self.probes["name"] == name]
        return rows[np.argsort(rows["seq"], kind="stable")]


def _matrix(frames, attribute, width):
    if not frames or width == 0:
        return np.zeros((len(frames), width))
    return np.array([list(getattr(f, attribute)) for f in frames], dtype=float).reshape(
        len(frames), width)


def result_from_chunks(chunks):
    """A Result from GetResult's stream of ResultChunk messages."""
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
    has_tau = bool(frames) and len(frames[0].tau) == n and n > 0
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
        q=_matrix(frames, "q", n), qd=_matrix(frames, "qd", n),
        tcp=np.array([(f.tcp_m.x, f.tcp_m.y, f.tcp_m.z) for f in frames],
                     dtype=float).reshape(len(frames), 3),
        tau=_matrix(frames, "tau", n if has_tau else 0),
        kinetic=np.array([f.kinetic_j for f in frames], dtype=float),
        potential=np.array([f.potential_j for f in frames], dtype=float),
        seq=np.array([f.seq for f in frames], dtype=np.int64),
        probes=probe_rows, stats=stats_dict(info), info=info)
