"""A handle on one run of the server: watch its frames, wait, fetch its result, cancel."""
from ._stubs import run_pb2, simulation_service_pb2 as service_pb2
from .errors import MbstreamError, rpc_errors
from .result import result_from_chunks

FINAL_STATES = frozenset(run_pb2.RunState.Name(s) for s in (
    run_pb2.FINISHED, run_pb2.DIVERGED, run_pb2.TOO_MUCH_WORK, run_pb2.ERROR_TEST_FAILURES,
    run_pb2.CONVERGENCE_FAILURES, run_pb2.FAILED, run_pb2.CANCELLED, run_pb2.INTERRUPTED))


class Run:
    """One run. `id` is its id ("r-..."), `info` the latest RunInfo seen (updated by
    refresh(), wait(), watch() and cancel()), `state` its state name, `missed` the frames
    the server dropped for this client while watching (it was too slow).

    Iterating the handle (`for frame in run:`) is watch(): the run's frames as they arrive,
    Frame messages (seq, t_s, q, qd, tcp_m, tau, ...), until the run ends."""

    def __init__(self, client, info, watch_call=None):
        self._client = client
        self.info = info
        self.id = info.id
        self.missed = 0
        self._watch_call = watch_call  # a WatchRun stream opened by Client.run(watch=True)

    def __repr__(self):
        return "<Run %s %s %s>" % (self.id, self.info.model_name, self.state)

    @property
    def state(self):
        return run_pb2.RunState.Name(self.info.state)

    @property
    def done(self):
        """The run has ended (as of the latest RunInfo seen)."""
        return self.state in FINAL_STATES

    def refresh(self):
        """The run's current RunInfo (GetRun)."""
        with rpc_errors():
            self.info = self._client.stub.GetRun(service_pb2.GetRunRequest(run_id=self.id))
        return self.info

    def _events(self, frames, progress_interval_s):
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

    def watch(self, progress_interval_s=0.0):
        """Yields the run's frames (Frame messages) as they arrive until the run ends. A
        client that joins late first gets the latest frame; one that reads too slowly gets
        the newest frames and `missed` counts the others."""
        for event in self._events(True, progress_interval_s):
            kind = event.WhichOneof("event")
            if kind == "progress":
                self.info = event.progress
            elif kind == "frames":
                self.missed += event.frames.missed
                for frame in event.frames.frames:
                    yield frame

    __iter__ = watch

    def progress(self, progress_interval_s=0.2):
        """Yields RunInfo progress events (every progress_interval_s of wall time) until the
        run ends; the last one has the final state."""
        for event in self._events(False, progress_interval_s):
            if event.WhichOneof("event") == "progress":
                self.info = event.progress
                yield event.progress

    def wait(self):
        """Blocks until the run ends; returns its final RunInfo."""
        if not self.done:
            for _ in self.progress(1.0):
                pass
        return self.info

    def result(self, wait=True, check=False):
        """The run's stored result (mbstream_client.Result: NumPy arrays and stats). Waits
        for the run to end first unless `wait` is False (the server then answers
        FAILED_PRECONDITION while it runs). With `check`, a run that did not finish raises
        MbstreamError(state, message); otherwise the partial result comes back with its
        state."""
        if wait:
            self.wait()
        with rpc_errors():
            chunks = self._client.stub.GetResult(service_pb2.GetResultRequest(run_id=self.id))
            result = result_from_chunks(chunks)
        self.info = result.info
        if check and not result.finished:
            raise MbstreamError(result.state, result.message or "run %s ended %s"
                                % (self.id, result.state))
        return result

    def cancel(self):
        """Asks the server to cancel the run; returns its RunInfo (CANCELLED once it stops)."""
        with rpc_errors():
            self.info = self._client.stub.CancelRun(service_pb2.CancelRunRequest(run_id=self.id))
        return self.info
