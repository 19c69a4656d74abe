#!/usr/bin/env python3
"""The seed's figure from a live run: the TCP the server computed and the probe a viewer
computed, x/y/z against time, with the median probe round-trip latency.

    tcp_vs_probe.py --server ADDR [--run RUN_ID] [--out tcp_vs_probe.png]

With --run, plots that run; without, starts the seed run (models/irb1600/seed-run.json,
paced by --realtime so that a viewer can follow it) and waits for it. Probe reports exist
only when a viewer answered the run's frames, e.g.
    mbstream-viewer --server ADDR --follow --offscreen
Without any, it says so and exits 0.
"""
import argparse
import sys

import numpy as np

import _common
import mbstream_client as mb


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    _common.add_server_argument(parser)
    parser.add_argument("--run", help="an existing run id; default: start the seed run")
    parser.add_argument("--probe", help="the probe to plot (default: the run's only probe)")
    parser.add_argument("--duration", type=float, default=20.0, help="s, of a new seed run")
    parser.add_argument("--realtime", type=float, default=1.0,
                        help="pace of a new seed run (1 = wall-clock, as the seed ran)")
    parser.add_argument("--out", default="tcp_vs_probe.png", help="PNG file to write")
    parser.add_argument("--require-probes", action="store_true",
                        help="exit 1 unless every frame has a probe within 1e-6 m of the TCP")
    args = parser.parse_args()

    with mb.connect(args.server, ca_file=args.ca, token=args.token) as server:
        if args.run:
            run = server.get_run(args.run)
        else:
            run = server.run("irb1600", _common.model_file("irb1600", "seed-run.json"),
                             duration=args.duration, realtime=args.realtime)
            print("started run %s (%.1f s simulated at realtime %g)"
                  % (run.id, args.duration, args.realtime))
        result = run.result()

    if len(result.probes) == 0:
        print("no probe reports in run %s (start a viewer: mbstream-viewer --server %s "
              "--follow --offscreen, then run this again)" % (result.run_id, args.server))
        return 1 if args.require_probes else 0
    probe = result.probe(args.probe)
    name = probe["name"][0]
    index = np.searchsorted(result.seq, probe["seq"])
    tcp_at_probe = result.tcp[index]
    gap = np.linalg.norm(np.column_stack([probe["x"], probe["y"], probe["z"]]) - tcp_at_probe,
                         axis=1)
    latency_ms = np.median(probe["latency_us"]) / 1000.0
    frames = sorted(set(probe["frame"].tolist()))
    print("run %s: %d frames, %d reports of probe '%s' (in frame %s)"
          % (result.run_id, len(result.t), len(probe), name, ", ".join(frames)))
    print("max |probe - TCP| %.3g m; median probe latency %.3f ms (p99 %.3f ms)"
          % (gap.max(), latency_ms, np.percentile(probe["latency_us"], 99) / 1000.0))

    if args.require_probes and (len(probe) != len(result.t) or gap.max() > 1e-6):
        print("expected a probe within 1e-6 m of the TCP for each of the %d frames"
              % len(result.t), file=sys.stderr)
        return 1

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    figure, axes = plt.subplots(3, 1, sharex=True, figsize=(8, 7))
    for k, axis in enumerate("xyz"):
        axes[k].plot(result.t, result.tcp[:, k], "-", color="C0", label="TCP (server)")
        axes[k].plot(probe["t"], probe[axis], ".", color="C1", markersize=3,
                     label="probe '%s' (viewer)" % name)
        axes[k].set_ylabel("%s (m)" % axis)
        axes[k].grid(True, alpha=0.3)
    axes[0].legend(loc="upper right")
    axes[-1].set_xlabel("t (s)")
    figure.suptitle("run %s: TCP vs probe; max gap %.2g m, median latency %.2f ms"
                    % (result.run_id, gap.max(), latency_ms))
    figure.tight_layout()
    figure.savefig(args.out, dpi=100)
    print("wrote %s" % args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
