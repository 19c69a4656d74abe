"""The client: one channel to a server and the calls of service mbstream.v1.Simulation."""
import os
from types import TracebackType
from typing import Any, Iterable, List, Mapping, Optional, Sequence, Type, Union

from ._stubs import model_pb2, replay_pb2, run_pb2
from ._stubs import simulation_service_pb2 as service_pb2
from ._stubs import simulation_service_pb2_grpc as service_grpc
from ._version import __version__
from .bundle import PathLike, read_model_bundle
from .compare import Comparison, compare_results
from .control import ControlLoop, control_start
from .channel import make_channel
from .errors import rpc_errors
from .mcap import StartLike, save_mcap
from .result import Result, result_from_chunks
from .run import Run
from .server_check import ServerCheck, check_server
from .spec import SpecLike, load_spec
from .sweep import Sweep, start_sweep, sweep_request


def _check_model(model: Any) -> None:
    """The model of a run is its id or name: a non-empty str (run(42) or run(None) would
    otherwise reach protobuf and fail there in its own words)."""
    if not isinstance(model, str):
        raise TypeError("model must be a model id or name (str), not %s" % type(model).__name__)
    if not model:
        raise ValueError("model is empty; give a model id or name (Client.models() lists them)")


class Client:
    """A connection to an mbstream server (see connect()). `stub` is the generated
    SimulationStub for calls the client does not wrap. Use as a context manager or call
    close()."""

    server: Optional[ServerCheck]

    def __init__(self, address: Optional[str] = None, ca_file: Optional[str] = None,
                 token: Optional[str] = None, token_file: Optional[str] = None,
                 cert_file: Optional[str] = None, key_file: Optional[str] = None):
        self.address, self.channel = make_channel(address, ca_file, token, token_file, cert_file,
                                                  key_file)
        self.stub = service_grpc.SimulationStub(self.channel)
        self.server = None  # set by check_server() (connect() calls it)

    def __enter__(self) -> "Client":
        return self

    def __exit__(self, kind: Optional[Type[BaseException]], value: Optional[BaseException],
                 traceback: Optional[TracebackType]) -> None:
        self.close()

    def close(self) -> None:
        """Closes the channel (streams still open are cancelled)."""
        self.channel.close()

    def check_server(self, timeout_s: float = 10.0) -> ServerCheck:
        """Asks the server which services it serves (gRPC reflection) and checks that it speaks
        this client's wire major version (mbstream.v1). Raises Unavailable when nothing
        answers within timeout_s (s), IncompatibleServer on another major version or a
        server that is not mbstream. connect() calls it."""
        self.server = check_server(self.channel, self.address, timeout_s, __version__)
        return self.server

    def submit(self, urdf_path_or_dir: PathLike, scene: Optional[PathLike] = None,
               assets: Iterable[PathLike] = (), name: Optional[str] = None,
               repair: bool = False, couple_mimic: bool = False,
               floating_base: bool = False,
               package_path: Iterable[PathLike] = ()) -> model_pb2.ModelInfo:
        """Submits a model: a URDF or SDFormat file (an SDFormat mechanism may close loops),
        or a directory with one .urdf or one .sdf (and its .scene and STL files; see
        read_model_bundle). Returns the server's ModelInfo (id "m-...": the
        same bundle gives the same id). A bad model raises BadRequest (INVALID_ARGUMENT)
        with the importer's messages. With repair=True the server repairs the defects
        published URDFs commonly carry, each listed in the ModelInfo's warnings. With
        couple_mimic=True each URDF joint with a <mimic> follows its leader (a closed-loop
        equation); without, it moves freely and a warning says so. With floating_base=True a
        URDF's root link moves freely (a free joint named after it). An SDFormat world's
        <include>s are found beside it and in `package_path` and sent written into it
        (docs/worlds.md)."""
        bundle = read_model_bundle(urdf_path_or_dir, scene, assets, name, package_path)
        bundle.repair = repair
        bundle.couple_mimic = couple_mimic
        bundle.floating_base = floating_base
        return self.submit_bundle(bundle)

    def submit_bundle(self, bundle: model_pb2.ModelBundle) -> model_pb2.ModelInfo:
        """Submits a ModelBundle message; returns its ModelInfo."""
        with rpc_errors():
            return self.stub.SubmitModel(service_pb2.SubmitModelRequest(bundle=bundle))

    def models(self) -> List[model_pb2.ModelInfo]:
        """Every model of the server (ModelInfo messages)."""
        with rpc_errors():
            return list(self.stub.ListModels(service_pb2.ListModelsRequest()).models)

    def model(self, model: str, include_bundle: bool = False
              ) -> Union[model_pb2.ModelInfo, "service_pb2.GetModelResponse"]:
        """One model's ModelInfo by id or name (with include_bundle: the GetModelResponse,
        info and bundle)."""
        with rpc_errors():
            response = self.stub.GetModel(
                service_pb2.GetModelRequest(model=model, include_bundle=include_bundle))
        return response if include_bundle else response.info

    def runs(self, model: str = "", limit: int = 0) -> List[run_pb2.RunInfo]:
        """Runs of the server, newest first (RunInfo messages); only `model`'s when given,
        at most `limit` when > 0."""
        runs = []
        request = service_pb2.ListRunsRequest(model=model, limit=limit)
        with rpc_errors():
            while True:  # one page at a time (a page never exceeds the message limit)
                response = self.stub.ListRuns(request)
                runs.extend(response.runs)
                if not response.next_page_token:
                    return runs
                request.page_token = response.next_page_token

    def run(self, model: str, spec: SpecLike = None, watch: bool = False,
            **overrides: Any) -> Run:
        """Starts a run of `model` (id or name) and returns its Run handle.

        spec: None (the server's defaults), a dict, a JSON file path or a RunSpec; overrides:
        RunSpec fields (rtol=1e-8, method="adams", drives=[...]) or the CLI's names
        (duration, output_interval, max_step, step), applied over the spec.
        watch=True opens the frame stream at once, so that `for frame in run:` sees the run
        from its first frames; iterate the returned handle to get them as they arrive."""
        _check_model(model)
        request = service_pb2.StartRunRequest(model=model, spec=load_spec(spec, **overrides))
        with rpc_errors():
            info = self.stub.StartRun(request)
            call = None
            if watch:
                call = self.stub.WatchRun(service_pb2.WatchRunRequest(run_id=info.id,
                                                                      frames=True))
        return Run(self, info, call)

    def control(self, model: str = "", spec: SpecLike = None, run_id: str = "",
                **overrides: Any) -> ControlLoop:
        """Your controller in the loop of a run, lockstep (control.py): starts a run of
        `model` with `spec` (with drives {"external": {"command": "effort", "period_s": h}}
        on the joints you command; overrides as for run()), or attaches to run `run_id`
        started with external drives. Use as a context manager and iterate it:

            with client.control("irb1600", spec) as loop:
                for state in loop:                      # t_k = k h: state.t, .q, .qd, .tcp
                    loop.send(effort=...)               # one value per loop.external_joints

        Raises BadRequest for a bad spec or command, PermissionDenied without the run role."""
        if run_id:
            start = control_start("", run_id=run_id)
        else:
            _check_model(model)
            start = control_start(model, load_spec(spec, **overrides))
        return ControlLoop(self.stub, start)

    def run_many(self, model: str, specs: Iterable[SpecLike],
                 **overrides: Any) -> List[Run]:
        """Starts one run of `model` per spec in ONE call (a sweep): either every run is
        queued or none is (a bad spec raises with its index: "specs[3]: ..."; more runs than
        the server's queue takes raise RESOURCE_EXHAUSTED). Each spec as in run(); the
        overrides apply to every spec. Returns the Run handles in the specs' order; fetch
        their results with results()."""
        _check_model(model)
        request = service_pb2.StartRunsRequest(
            model=model, specs=[load_spec(spec, **overrides) for spec in specs])
        with rpc_errors():
            response = self.stub.StartRuns(request)
        return [Run(self, info) for info in response.runs]

    def sweep(self, model: str, spec: SpecLike = None,
              grid: Optional[Mapping[str, Iterable[Any]]] = None,
              points: Optional[Sequence[Mapping[str, Any]]] = None, keep: str = "summary",
              window: int = 32, progress: bool = False, **overrides: Any) -> Any:
        """A parameter sweep as one job, its table as a pandas DataFrame (a row per run, in
        point order: run_id, the swept values, state, trust, cost, accuracy and, per joint,
        tracking_error_max:JOINT, effort_peak:JOINT, effort_rms:JOINT, q_final:JOINT; the
        columns of `mbstream sweep`'s sweep.csv): start_sweep(...).wait(progress).

        grid: {path: values} (every combination, the first path varying slowest) or points:
        [{path: value, ...}, ...]; a path names a RunSpec field as in its JSON, e.g. "rtol",
        "drives[1].pd_servo.kp", "drives[joint=joint2].pd_servo.kd", "initial_q[0]".
        keep: what each run keeps ("summary": no frames, the default; "final", "every:N",
        "all": fetch them with result(run_id)). The server stores the sweep and queues at most
        `window` of its runs at a time, whether or not this client follows it (Ctrl-C stops
        following only: Sweep(client, attrs["sweep_id"]).wait() picks it up again).
        progress=True shows the server's count of the sweep on stderr. The table's
        attrs["sweep_id"] names the sweep (sweep_progress, cancel_sweep); attrs["cancelled"]
        says it was cancelled before every point ran. spec and overrides as in run().
        Needs pandas."""
        return self.start_sweep(model, spec, grid, points, keep, window,
                                **overrides).wait(progress)

    def start_sweep(self, model: str, spec: SpecLike = None,
                    grid: Optional[Mapping[str, Iterable[Any]]] = None,
                    points: Optional[Sequence[Mapping[str, Any]]] = None, keep: str = "summary",
                    window: int = 32, **overrides: Any) -> Sweep:
        """Starts a sweep (as sweep()) and returns at once: a Sweep, whose wait() returns the
        table and whose id any client can follow with Sweep(client, id).wait()."""
        _check_model(model)
        request = sweep_request(model, load_spec(spec, keep=keep, **overrides), grid, points)
        return start_sweep(self, request, window)

    def sweep_handle(self, sweep_id: str) -> Sweep:
        """The Sweep of id `sweep_id` (started by any client), to wait() for or cancel()."""
        return Sweep(self, sweep_id)

    def sweep_progress(self, sweep_id: str) -> service_pb2.SweepProgress:
        """A sweep's progress as the server counts it (any replica of a cluster): total_points,
        started_runs, ended_runs, states (a SweepStateCount per state), cancelled, window, and
        the first 1,000 run_ids in point order with their points. NotFound for an unknown id."""
        with rpc_errors():
            return self.stub.GetSweep(service_pb2.GetSweepRequest(sweep_id=sweep_id))

    def cancel_sweep(self, sweep_id: str) -> service_pb2.SweepProgress:
        """Cancels a sweep: its queued and running runs, and the points not queued yet (the
        sweep() filling its table stops there; its table's attrs["cancelled"] is True). Returns
        once its runs have ended, with its progress then."""
        with rpc_errors():
            return self.stub.CancelSweep(service_pb2.CancelSweepRequest(sweep_id=sweep_id))

    def results(self, runs: Iterable[Union[Run, str]], wait: bool = True) -> List["Result"]:
        """The results of several runs (Run handles or ids) in ONE call, in the order given;
        each waits for its run's end unless `wait` is False (see Run.result)."""
        asked = list(runs)
        handles = [run if isinstance(run, Run) else None for run in asked]
        ids = [run.id if isinstance(run, Run) else run for run in asked]
        request = service_pb2.GetResultsRequest(run_ids=ids, wait=wait)
        results: List[Result] = []
        with rpc_errors():
            chunks: List[Any] = []
            for chunk in self.stub.GetResults(request):
                if chunk.HasField("info") and chunks:
                    results.append(result_from_chunks(chunks, self.stub))
                    chunks = []
                chunks.append(chunk)
            if chunks:
                results.append(result_from_chunks(chunks, self.stub))
        for handle, result in zip(handles, results):
            if handle is not None:
                handle.info = result.info
        return results

    def get_run(self, run_id: str) -> Run:
        """A Run handle on an existing run."""
        with rpc_errors():
            return Run(self, self.stub.GetRun(service_pb2.GetRunRequest(run_id=run_id)))

    def result(self, run_id: str, wait: bool = True, check: bool = False,
               probe_set: str = "") -> "Result":
        """The result of run `run_id` (see Run.result); with `probe_set`, the probes of that
        replay of it (probe_sets())."""
        return self.get_run(run_id).result(wait=wait, check=check, probe_set=probe_set)

    def export_mcap(self, run: Union[Run, str], path: Union[str, "os.PathLike[str]"],
                    compression: str = "zstd", start: StartLike = None, probe_set: str = "",
                    wait: bool = True) -> str:
        """Writes run `run` (a Run handle or id) as one MCAP file at `path` (see
        Result.to_mcap), its frames never fetched here. Returns `path`."""
        if isinstance(run, Run):
            return run.to_mcap(path, compression, start, probe_set, wait)
        save_mcap(self.stub, run, path, compression, start, probe_set, wait)
        return os.fspath(path)

    def probe_sets(self, run_id: str) -> List[replay_pb2.ProbeSet]:
        """The probe sets of the replays of run `run_id`, oldest first: each one's id (for
        result(run_id, probe_set=...)), viewer, scene and report count."""
        with rpc_errors():
            return list(self.stub.ListProbeSets(
                replay_pb2.ListProbeSetsRequest(run_id=run_id)).sets)

    def replay(self, run_id: str, speed: float = 1.0) -> run_pb2.RunInfo:
        """Makes the server stream the stored run `run_id` to its --follow viewers as if it
        were running now, at `speed` (simulated s per wall s); returns at once."""
        with rpc_errors():
            return self.stub.ReplayRun(replay_pb2.ReplayRunRequest(run_id=run_id, speed=speed))

    def delete_runs(self, runs: Iterable[Union[Run, str]]) -> List[run_pb2.RunInfo]:
        """Deletes runs (Run handles or ids) whole: frames, probe reports and probe sets, each
        run in one transaction; a queued or running run is cancelled first. Needs an admin
        token. Every run is looked up first: NotFound names an unknown one and nothing is
        deleted. Returns the runs as they were (ended) just before deletion."""
        ids = [run.id if isinstance(run, Run) else run for run in runs]
        with rpc_errors():
            return list(self.stub.DeleteRuns(service_pb2.DeleteRunsRequest(run_ids=ids)).runs)

    def delete_model(self, model: str, with_runs: bool = False
                     ) -> service_pb2.DeleteModelResponse:
        """Deletes a submitted model (id or name). FailedPrecondition while it has runs unless
        with_runs (they are deleted first, as delete_runs does), and for a built-in model.
        Needs an admin token. Returns the model's info and the runs deleted with it."""
        _check_model(model)
        with rpc_errors():
            return self.stub.DeleteModel(
                service_pb2.DeleteModelRequest(model=model, with_runs=with_runs))

    def keep(self, run: Union[Run, str], keep: bool = True) -> run_pb2.RunInfo:
        """Marks an ended run (Run handle or id) to be kept: the server's retention
        (--retain-runs, --retain-days) never deletes it; keep=False: no longer. Returns its info
        (info.keep). FailedPrecondition while the run is queued or running."""
        run_id = run.id if isinstance(run, Run) else run
        with rpc_errors():
            return self.stub.SetKeep(service_pb2.SetKeepRequest(run_id=run_id, keep=keep))

    def retention_plan(self) -> service_pb2.RetentionPlanResponse:
        """A dry run of the server's retention: its policy (retain_runs, retain_days; 0 = no
        limit) and the runs it would delete now (runs, oldest first). Nothing is deleted."""
        with rpc_errors():
            return self.stub.RetentionPlan(service_pb2.RetentionPlanRequest())

    def storage(self) -> service_pb2.GetStorageResponse:
        """Where the server's data is and what it takes (admin token): backend and location,
        frame_bytes, probe_bytes, run_bytes, model_bytes, disk_bytes, free_bytes (-1 unknown)
        against min_free_bytes (below_min_free: new runs are refused), runs by state, models
        (most bytes first) and what retention would delete now (retention_runs,
        retention_bytes)."""
        with rpc_errors():
            return self.stub.GetStorage(service_pb2.GetStorageRequest())

    def backup(self, directory: str) -> service_pb2.BackupStorageResponse:
        """A consistent copy of the server's live SQLite store into `directory`, a new or empty
        directory on the server's machine (admin token); `mbstream-server --data DIRECTORY`
        starts from it. FailedPrecondition on a PostgreSQL store (pg_dump instead)."""
        with rpc_errors():
            return self.stub.BackupStorage(service_pb2.BackupStorageRequest(dir=directory))

    def compare(self, run_id: str, ghost_run_id: str) -> Comparison:
        """Runs `run_id` and `ghost_run_id` side by side on their common time grid, as
        `mbstream-viewer --run A --compare B` shows them: the TCP distance at each common
        time and its maximum (see compare_results; BadRequest-like ValueError when their
        joints differ or their grids cannot be aligned)."""
        return compare_results(self.result(run_id), self.result(ghost_run_id))


def connect(address: Optional[str] = None, ca_file: Optional[str] = None,
            token: Optional[str] = None, *, check: bool = True, timeout_s: float = 10.0,
            **options: Any) -> Client:
    """A Client for the server at `address` (host:port or unix:/path; default
    $MBSTREAM_SERVER, else 127.0.0.1:50051), checked at once (check=True): a server must
    answer within timeout_s (s), else Unavailable, and speak this client's wire major version
    (mbstream.v1), else IncompatibleServer saying which version it speaks.

    ca_file: PEM CA of the server's certificate: TLS (grpc.ssl_channel_credentials);
    without it the channel is plaintext, meant for loopback and unix sockets.
    token: sent as `authorization: Bearer <token>` metadata on every call (refused in
    plaintext to a non-local address). More options: token_file (its first word is the
    token), cert_file and key_file (a client certificate for TLS). check=False connects
    lazily, as a plain gRPC channel does (the first call then fails if no server answers)."""
    client = Client(address, ca_file, token, **options)
    if check:
        try:
            client.check_server(timeout_s)
        except BaseException:
            client.close()
            raise
    return client
