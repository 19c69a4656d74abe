#!/usr/bin/python3
"""Checks a results directory: every TCP frame has a viewer probe at the same place.

    check_probes.py RESULTS_DIR [--frames N] [--probe NAME] [--tol METRES]

Reads tcp.csv (`t,x,y,z`) and probes.csv (`seq,t,name,x,y,z,latency_us`); a probe belongs to
the frame with the same simulation time (within 1e-9 s). Exit 0 when there are N frames
(if given) and each has a probe named NAME within TOL of its TCP; otherwise exit 1 and say
which frames fail. Standard library only (run by /usr/bin/python3).
"""
import argparse
import csv
import math
import os
import sys


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results")
    parser.add_argument("--frames", type=int, default=None, help="expected number of frames")
    parser.add_argument("--probe", default="Tcp", help="probe name (default Tcp)")
    parser.add_argument("--tol", type=float, default=1e-6, help="metres (default 1e-6)")
    args = parser.parse_args()

    tcp_path = os.path.join(args.results, "tcp.csv")
    probe_path = os.path.join(args.results, "probes.csv")
    if not os.path.exists(tcp_path):
        print(f"probes: FAIL: {tcp_path} is missing")
        return 1
    tcp = [(float(r["t"]), float(r["x"]), float(r["y"]), float(r["z"])) for r in read_rows(tcp_path)]
    if args.frames is not None and len(tcp) != args.frames:
        print(f"probes: FAIL: tcp.csv has {len(tcp)} frames, expected {args.frames}")
        return 1
    if not os.path.exists(probe_path):
        print(f"probes: FAIL: {probe_path} is missing (no viewer answered)")
        return 1

    # Probes keyed by time rounded to the nanosecond; several replies for one frame may
    # exist (a viewer answers each frame it sees once): the closest one counts.
    by_time = {}
    latencies = []
    for r in read_rows(probe_path):
        if r["name"] != args.probe:
            continue
        key = round(float(r["t"]) * 1e9)
        by_time.setdefault(key, []).append((float(r["x"]), float(r["y"]), float(r["z"])))
        latencies.append(float(r["latency_us"]))

    missing, off = [], []
    worst = 0.0
    for t, x, y, z in tcp:
        candidates = by_time.get(round(t * 1e9), [])
        if not candidates:
            missing.append(t)
            continue
        d = min(math.dist((x, y, z), p) for p in candidates)
        worst = max(worst, d)
        if d > args.tol:
            off.append((t, d))

    if missing or off:
        print(f"probes: FAIL: {len(tcp)} frames, {len(missing)} without a '{args.probe}' probe, "
              f"{len(off)} farther than {args.tol:g} m from the TCP")
        if missing:
            print("  first frames without a probe: t = " + ", ".join(f"{t:g}" for t in missing[:10]))
        for t, d in off[:10]:
            print(f"  t = {t:g}: probe {d:.3g} m from the TCP")
        return 1
    latencies.sort()
    median = latencies[len(latencies) // 2] if latencies else float("nan")
    print(f"probes: OK: {len(tcp)} frames, each with a '{args.probe}' probe; largest distance "
          f"to the TCP {worst:.3g} m (tolerance {args.tol:g} m); median round trip {median:.0f} us")
    return 0


if __name__ == "__main__":
    sys.exit(main())
