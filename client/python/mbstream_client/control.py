"""Your controller in the loop of a run, lockstep (Simulation.Control,
proto/mbstream/v1/control.proto).

    with client.control("irb1600", spec) as loop:       # spec: drives {"external": {...}}
        for state in loop:                              # the state at t_k = k h
            loop.send(effort=-kd * state.qd)            # held over [t_k, t_k+1)
    print(loop.info.state, loop.info.message)           # the run's final info

At each control instant the server sends the state and waits for the command; the next state
is the acknowledgement that the step ran. Commands are NumPy arrays (or sequences) in the order
of `loop.external_joints`, or dicts by joint name. A command the server refuses (not finite,
the wrong length, beyond 1e7, a second one for a state) raises BadRequest from the loop, and
the run stops FAILED. Leaving the `with` block early (an exception, a break) cancels the run.
"""
import queue
from typing import Any, Iterator, List, Mapping, Optional, Sequence, Union

import grpc
import numpy as np

from ._stubs import control_pb2, run_pb2
from .errors import bad_request, from_rpc_error

Command = Union[Sequence[float], "np.ndarray", Mapping[str, float]]


def _xyz(v: Any) -> "np.ndarray":
    return np.array([v.x, v.y, v.z], dtype=float)


class Contact:
    """One active contact at a state (contacts.csv's columns): the geometry pair (`link_a`,
    `collision_a`, `link_b`, `collision_b`), `point` (m), the unit `normal` from b toward a,
    `depth` (m), `normal_force` (N) and `friction` (N, a 3-vector) on a, world frame."""

    def __init__(self, message: Any):
        self.link_a = message.link_a
        self.collision_a = message.collision_a
        self.link_b = message.link_b
        self.collision_b = message.collision_b
        self.point = _xyz(message.point_m)
        self.normal = _xyz(message.normal)
        self.depth = float(message.depth_m)
        self.normal_force = float(message.normal_force_n)
        self.friction = _xyz(message.friction_force_n)

    def __repr__(self) -> str:
        return "Contact(%s/%s on %s/%s, %.6g N)" % (self.link_a, self.collision_a, self.link_b,
                                                   self.collision_b, self.normal_force)


class ControlState:
    """The state at control instant t_k = k h: step k, t (s), q (rad or m, `position_names`'
    order) and qd (rad/s or m/s, `velocity_names`' order, the same as `joint_names`) as NumPy
    arrays, the TCP's position (m, base frame), `sensors` (an (n, 3) array, m, world frame:
    the spec's sensor points in `sensor_names`' order; `state.sensor("tip")` is one) and
    `contacts` (the active contacts, a list of Contact). `state["joint2"]` is joint2's q,
    `state.velocity("joint2")` its qd. Without free or ball joints q and qd are both in the
    joints' order; with them q has a free joint NAME's 7 positions (`state["base.z"]`,
    `state["base.qw"]`: x y z, then the unit quaternion scalar first) and qd its 6 velocities
    (`state.velocity("base.wz")`: vx vy vz in the world, wx wy wz in the body frame)."""

    def __init__(self, message: "control_pb2.ControlState", joint_names: List[str],
                 sensor_names: Optional[List[str]] = None,
                 position_names: Optional[List[str]] = None):
        self.position_names = position_names or joint_names
        self.velocity_names = joint_names
        self.step = int(message.step)
        self.t = float(message.t_s)
        self.q = np.array(message.q, dtype=float)
        self.qd = np.array(message.qd, dtype=float)
        self.tcp = np.array([message.tcp.x, message.tcp.y, message.tcp.z])
        self.final = bool(message.final)
        self.joint_names = joint_names
        self.sensor_names = sensor_names or []
        self.sensors = np.array([[p.x, p.y, p.z] for p in message.sensors],
                                dtype=float).reshape(-1, 3)
        self.contacts = [Contact(c) for c in message.contacts]

    def __getitem__(self, coordinate: str) -> float:
        """The position coordinate `coordinate` (a joint's name, or NAME.x ... NAME.qz)."""
        return float(self.q[self._index(coordinate, self.position_names, "position")])

    def velocity(self, coordinate: str) -> float:
        """The velocity coordinate `coordinate` (a joint's name, or NAME.vx ... NAME.wz)."""
        return float(self.qd[self._index(coordinate, self.velocity_names, "velocity")])

    @staticmethod
    def _index(coordinate: str, names: List[str], what: str) -> int:
        if coordinate not in names:
            raise bad_request("no %s coordinate %r; the model's are %s"
                              % (what, coordinate, ", ".join(names)))
        return names.index(coordinate)

    def sensor(self, name: str) -> "np.ndarray":
        """The sensor point `name`'s position (m, world frame)."""
        if name not in self.sensor_names:
            raise bad_request("no sensor point %r; the run's are %s"
                              % (name, ", ".join(self.sensor_names) or "none"))
        return self.sensors[self.sensor_names.index(name)]

    def __repr__(self) -> str:
        return "ControlState(step=%d, t=%.6g s)" % (self.step, self.t)


class ControlLoop:
    """One controlled run (Client.control). Iterate it for the states; answer each with
    send(). After the loop: `info` (the run's final RunInfo), `final` (the last state, at the
    run's end), `run_id`."""

    def __init__(self, stub: Any, start: "control_pb2.ControlStart"):
        self._requests: "queue.Queue[Optional[control_pb2.ControlRequest]]" = queue.Queue()
        self._requests.put(control_pb2.ControlRequest(start=start))
        self._call = stub.Control(iter(self._requests.get, None))
        self._pending: Optional[int] = None
        self._closed = False
        self.info: Optional[run_pb2.RunInfo] = None
        self.final: Optional[ControlState] = None
        try:
            first = next(self._call)
        except grpc.RpcError as error:
            self._closed = True
            raise from_rpc_error(error) from None
        started = first.started
        self.run_id: str = started.run.id
        self.joint_names: List[str] = list(started.joint_names)
        self.external_joints: List[str] = list(started.external_joints)
        self.commands: List[str] = list(started.commands)
        self.period_s: float = started.period_s
        self.sensor_names: List[str] = list(started.sensor_names)
        # A server before position_names sent none: its q was in joint_names' order.
        self.position_names: List[str] = list(started.position_names) or self.joint_names
        self.velocity_names: List[str] = list(started.velocity_names) or self.joint_names

    def __enter__(self) -> "ControlLoop":
        return self

    def __exit__(self, kind: Any, value: Any, traceback: Any) -> None:
        if kind is not None or self.info is None:
            self.cancel()  # left early: the run is cancelled
        self.close()

    def __iter__(self) -> Iterator[ControlState]:
        try:
            for response in self._call:
                which = response.WhichOneof("kind")
                if which == "state":
                    state = ControlState(response.state, self.joint_names, self.sensor_names,
                                         self.position_names)
                    if state.final:
                        self.final = state
                        continue
                    self._pending = state.step
                    yield state
                elif which == "ended":
                    self.info = response.ended
                    self.close()  # the server then ends the stream with its status
        except grpc.RpcError as error:
            raise from_rpc_error(error) from None
        finally:
            self._pending = None
            self.close()

    def send(self, values: Optional[Command] = None, *, effort: Optional[Command] = None,
             position: Optional[Command] = None, velocity: Optional[Command] = None) -> None:
        """The command for the state just received, one value per external joint (in
        `external_joints`' order, or a dict by name): effort in N*m or N, position in rad or
        m, velocity in rad/s or m/s, as each drive's command says. The keyword names the
        command kind and must match the drives' (`values=` takes any)."""
        given = {"effort": effort, "position": position, "velocity": velocity}
        kinds = [k for k, v in given.items() if v is not None]
        if (values is not None) + len(kinds) != 1:
            raise bad_request("send: give exactly one of values, effort, position or velocity")
        if kinds:
            kind = kinds[0]
            wrong = [j for j, c in zip(self.external_joints, self.commands) if c != kind]
            if wrong:
                raise bad_request("send(%s=...): joints %s take %s commands; use values=[...]"
                                  % (kind, ", ".join(wrong), "/".join(sorted(set(
                                      c for j, c in zip(self.external_joints, self.commands)
                                      if j in wrong)))))
            values = given[kind]
        if values is None:  # unreachable: exactly one was given
            raise bad_request("send: no command given")
        if self._pending is None:
            raise bad_request("send: no state awaits a command; send once per state, inside "
                              "the `for state in loop` body")
        self._requests.put(control_pb2.ControlRequest(command=control_pb2.ControlCommand(
            step=self._pending, values=self._vector(values))))
        self._pending = None

    def _vector(self, values: Command) -> List[float]:
        if isinstance(values, Mapping):
            unknown = sorted(set(values) - set(self.external_joints))
            if unknown:
                raise bad_request("send: %s are not external joints of run %s (%s)"
                                  % (", ".join(unknown), self.run_id,
                                     ", ".join(self.external_joints)))
            missing = [j for j in self.external_joints if j not in values]
            if missing:
                raise bad_request("send: no command for %s" % ", ".join(missing))
            return [float(values[j]) for j in self.external_joints]
        return [float(v) for v in np.asarray(values, dtype=float).ravel()]

    def cancel(self) -> None:
        """Cancels the stream: the server cancels the run."""
        if not self._closed:
            self._call.cancel()

    def close(self) -> None:
        """Half-closes the stream (the server ends it once the run has ended)."""
        if not self._closed:
            self._closed = True
            self._requests.put(None)


def control_start(model: str, spec: Any = None, run_id: str = "") -> "control_pb2.ControlStart":
    """The stream's first message: a new run (model, spec) or an existing one (run_id)."""
    if run_id:
        return control_pb2.ControlStart(run_id=run_id)
    return control_pb2.ControlStart(model=model, spec=spec)


__all__ = ["Contact", "ControlLoop", "ControlState", "control_start"]
