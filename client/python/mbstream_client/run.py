"""A handle on one run of the server: watch its frames and progress, wait, fetch its result,
cancel."""
import os
import sys
from typing import TYPE_CHECKING, Any, Iterator, Optional, TextIO, Union

from ._stubs import frame_pb2, run_pb2, simulation_service_pb2 as service_pb2
from .errors import RunFailed, rpc_errors
from .mcap import StartLike, save_mcap
from .result import Result, result_from_chunks

if TYPE_CHECKING:  # pragma: no cover
    from .client import Client

FINAL_STATES = frozenset(run_pb2.RunState.Name(s) for s in (
    run_pb2.FINISHED, run_pb2.DIVERGED, run_pb2.TOO_MUCH_WORK, run_pb2.ERROR_TEST_FAILURES,
    run_pb2.CONVERGENCE_FAILURES, run_pb2.FAILED, run_pb2.CANCELLED, run_pb2.INTERRUPTED))

Frame = frame_pb2.Frame
RunInfo = run_pb2.RunInfo


class ProgressBar:
    """The progress of a run in simulated time (s): a tqdm bar when tqdm is installed, else a
    plain text line at each tenth of the run (and at its end) on `stream` (stderr)."""

    def __init__(self, run_id: str, stream: Optional[TextIO] = None, use_tqdm: bool = True):
        self._run_id = run_id
        self._stream = stream or sys.stderr
        self._bar: Any = None
        self._tqdm: Any = None
        if use_tqdm:
            try:
                from tqdm import tqdm
                self._tqdm = tqdm
            except ImportError:
                pass
        self._printed_tenth = -1
        self.closed = False

    def update(self, info: "run_pb2.RunInfo") -> None:
        """Shows `info`: t_s of duration_s simulated, its frames and state."""
        if self.closed:
            return
        total = info.duration_s if info.duration_s > 0 else None
        state = run_pb2.RunState.Name(info.state)
        if self._tqdm is not None:
            if self._bar is None:
                self._bar = self._tqdm(total=total, unit="s", desc=self._run_id,
                                       file=self._stream, leave=True,
                                       bar_format="{desc}: {percentage:3.0f}%|{bar}| "
                                                  "{n:.2f}/{total:.2f} s simulated "
                                                  "[{elapsed}<{remaining}{postfix}]")
            self._bar.n = min(info.t_s, total) if total else info.t_s
            self._bar.set_postfix_str("%s, %d frames" % (state, info.frames), refresh=False)
            self._bar.refresh()
        else:
            tenth = int(10 * info.t_s / total) if total else 0
            final = state in FINAL_STATES
            if tenth > self._printed_tenth or final:
                self._printed_tenth = tenth
                self._stream.write("%s: %5.1f%% %.2f/%s s simulated, %d frames, %s\n" % (
                    self._run_id, 100.0 * info.t_s / total if total else 0.0, info.t_s,
                    "%.2f" % total if total else "?", info.frames, state))
                self._stream.flush()
        if state in FINAL_STATES:
            self.close()

    def close(self) -> None:
        if self._bar is not None and not self.closed:
            self._bar.close()
        self.closed = True


class Run:
    """One run. `id` is its id ("r-..."), `info` the latest RunInfo seen (updated by
    refresh(), wait(), watch() and cancel()), `state` its state name, `missed` the frames
    the server dropped for this client while watching (it was too slow).

    Iterating the handle (`for frame in run:`) is watch(): the run's frames as they arrive,
    Frame messages (seq, t_s in s, q in rad or m, qd, tcp_m in m in the base frame, tau in
    N*m or N, ...), until the run ends."""

    def __init__(self, client: "Client", info: "run_pb2.RunInfo", watch_call: Any = None):
        self._client = client
        self.info = info
        self.id: str = info.id
        self.missed = 0
        self._watch_call = watch_call  # a WatchRun stream opened by Client.run(watch=True)

    def __repr__(self) -> str:
        return "<Run %s %s %s>" % (self.id, self.info.model_name, self.state)

    @property
    def state(self) -> str:
        """The state name: "QUEUED", "RUNNING", "FINISHED", "DIVERGED", "CANCELLED", ..."""
        return run_pb2.RunState.Name(self.info.state)

    @property
    def done(self) -> bool:
        """The run has ended (as of the latest RunInfo seen)."""
        return self.state in FINAL_STATES

    def refresh(self) -> "run_pb2.RunInfo":
        """The run's current RunInfo (GetRun)."""
        with rpc_errors():
            self.info = self._client.stub.GetRun(service_pb2.GetRunRequest(run_id=self.id))
        return self.info

    def _events(self, frames: bool, progress_interval_s: float) -> Iterator[Any]:
        call = self._watch_call if frames else None
        self._watch_call = None
        if call is None:
            call = self._client.stub.WatchRun(service_pb2.WatchRunRequest(
                run_id=self.id, frames=frames, progress_interval_s=progress_interval_s))
        try:
            with rpc_errors():
                for event in call:
                    yield event
        finally:
            call.cancel()  # a no-op when the stream ended; stops it when the caller quit early

    def watch(self, progress: Union[bool, ProgressBar] = False, *, events: bool = False,
              progress_interval_s: float = 0.0
              ) -> Iterator[Union["frame_pb2.Frame", "run_pb2.RunInfo"]]:
        """Iterates over the run as it goes, until it ends.

        Yields its frames (Frame messages) as they arrive; with events=True also its progress
        (RunInfo messages: state, t_s of duration_s simulated, frames so far), both in
        arrival order (tell them apart with isinstance(item, mbstream_client.RunInfo)); the
        last progress has the final state. progress=True draws a progress bar of simulated
        time on stderr (tqdm when installed, else a plain text line per tenth of the run);
        progress_interval_s: s of wall time between progress events (0: the server's 0.2).

        A client that joins late first gets the latest frame; one that reads too slowly gets
        the newest frames and `missed` counts the others."""
        bar = progress if isinstance(progress, ProgressBar) else (
            ProgressBar(self.id) if progress else None)
        try:
            for event in self._events(True, progress_interval_s):
                kind = event.WhichOneof("event")
                if kind == "progress":
                    self.info = event.progress
                    if bar is not None:
                        bar.update(event.progress)
                    if events:
                        yield event.progress
                elif kind == "frames":
                    self.missed += event.frames.missed
                    for frame in event.frames.frames:
                        yield frame
        finally:
            if bar is not None:
                bar.close()

    def __iter__(self) -> Iterator["frame_pb2.Frame"]:
        return self.watch()

    def progress(self, progress_interval_s: float = 0.2) -> Iterator["run_pb2.RunInfo"]:
        """Yields RunInfo progress events (every progress_interval_s s of wall time) until the
        run ends; the last one has the final state."""
        for event in self._events(False, progress_interval_s):
            if event.WhichOneof("event") == "progress":
                self.info = event.progress
                yield event.progress

    def wait(self, progress: bool = False) -> "run_pb2.RunInfo":
        """Blocks until the run ends; returns its final RunInfo. progress=True draws a
        progress bar meanwhile (see watch)."""
        if not self.done:
            bar = ProgressBar(self.id) if progress else None
            try:
                for info in self.progress(0.2 if progress else 1.0):
                    if bar is not None:
                        bar.update(info)
            finally:
                if bar is not None:
                    bar.close()
        return self.info

    def result(self, wait: bool = True, check: bool = False, probe_set: str = "") -> Result:
        """The run's stored result (mbstream_client.Result: NumPy arrays and stats). Waits
        for the run to end first unless `wait` is False (the server then answers
        FAILED_PRECONDITION while it runs); the server does the waiting, in the same call. With `check`, a run that did not finish raises
        RunFailed (code: its state, message: the server's); otherwise the partial result
        comes back with its state. probe_set: the id of one of the run's replay probe sets
        (Client.probe_sets): `probes` then holds that replay's reports, not the live run's."""
        with rpc_errors():
            chunks = self._client.stub.GetResult(
                service_pb2.GetResultRequest(run_id=self.id, probe_set=probe_set, wait=wait))
            result = result_from_chunks(chunks, self._client.stub, probe_set)
        self.info = result.info
        if check and not result.finished:
            raise RunFailed(result.state, result.message or "run %s ended %s"
                            % (self.id, result.state))
        return result

    def to_mcap(self, path: Union[str, "os.PathLike[str]"], compression: str = "zstd",
                start: StartLike = None, probe_set: str = "", wait: bool = True) -> str:
        """Writes the run as one MCAP file at `path`, as Result.to_mcap does, without
        fetching its frames here (the server writes the file; memory stays small for a run of
        any length). Waits for the run's end unless `wait` is False. Returns `path`."""
        self.info = save_mcap(self._client.stub, self.id, path, compression, start, probe_set,
                              wait)
        return os.fspath(path)

    def cancel(self) -> "run_pb2.RunInfo":
        """Asks the server to cancel the run; returns its RunInfo (CANCELLED once it stops)."""
        with rpc_errors():
            self.info = self._client.stub.CancelRun(service_pb2.CancelRunRequest(run_id=self.id))
        return self.info
