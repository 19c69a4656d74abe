#!/usr/bin/python3
"""Runs per second of a sweep: starts RUNS short runs of a model on one gRPC channel (through a
load balancer, each call may reach another replica), at most WINDOW of them unfinished at a
time (under the servers' --max-queued-runs), polls GetRun until each has ended, and prints
the rate and the final states. Exit 0 only when every run FINISHED. Used by netns.sh --client
rate for docs/performance.md.

    sweep_rate.py --server ADDR --ca CA --token-file F --stubs DIR [--runs N] [--window W]
                  [--model irb1600] [--spec SPEC.json] [--duration S]

--stubs: a folder holding the Python code protoc generated from proto/ (netns.sh makes it).
Standard library plus Debian's python3-grpcio and python3-protobuf.
"""
import argparse
import collections
import sys
import time


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--server", required=True)
    parser.add_argument("--ca", required=True)
    parser.add_argument("--token-file", required=True)
    parser.add_argument("--stubs", required=True)
    parser.add_argument("--runs", type=int, default=1000)
    parser.add_argument("--window", type=int, default=48)
    parser.add_argument("--model", default="irb1600")
    parser.add_argument("--spec", default="models/irb1600/seed-run.json")
    parser.add_argument("--duration", type=float, default=1.0, help="s simulated per run")
    args = parser.parse_args()
    sys.path.insert(0, args.stubs)
    import grpc
    from google.protobuf import json_format
    from mbstream.v1 import run_pb2, run_spec_pb2, simulation_service_pb2 as service
    from mbstream.v1 import simulation_service_pb2_grpc

    with open(args.ca, "rb") as f:
        credentials = grpc.ssl_channel_credentials(f.read())
    with open(args.token_file) as f:
        token = f.read().split()[0]
    metadata = (("authorization", "Bearer " + token),)
    channel = grpc.secure_channel(args.server, credentials)
    stub = simulation_service_pb2_grpc.SimulationStub(channel)
    with open(args.spec) as f:
        spec = json_format.Parse(f.read(), run_spec_pb2.RunSpec())
    spec.duration_s = args.duration

    final = collections.Counter()
    pending = []
    started = 0
    begin = time.monotonic()
    while started < args.runs or pending:
        while started < args.runs and len(pending) < args.window:
            request = service.StartRunRequest(model=args.model, spec=spec)
            pending.append(stub.StartRun(request, metadata=metadata).id)
            started += 1
        still = []
        for run_id in pending:
            info = stub.GetRun(service.GetRunRequest(run_id=run_id), metadata=metadata)
            name = run_pb2.RunState.Name(info.state)
            if name in ("QUEUED", "RUNNING"):
                still.append(run_id)
            else:
                final[name] += 1
        if len(still) == len(pending) and started == args.runs:
            time.sleep(0.01)  # nothing ended yet: poll again shortly
        pending = still
    elapsed = time.monotonic() - begin
    states = ", ".join("%s %d" % item for item in sorted(final.items()))
    print("sweep_rate: %d runs in %.2f s: %.1f runs/s (%s)"
          % (args.runs, elapsed, args.runs / elapsed, states))
    return 0 if final["FINISHED"] == args.runs else 1


if __name__ == "__main__":
    sys.exit(main())
