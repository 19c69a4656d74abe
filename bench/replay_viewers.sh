#!/usr/bin/env bash
# Frames per second of an unpaced replay (--speed 0) to N real offscreen viewers at once
# (Xvfb), each posing the IRB 1600 scene and answering every frame with its probe.
#
#   bench/replay_viewers.sh [N ...]     (default: 1 10)
#
# Starts its own mbstream-server on a free port, stores one run of FRAMES frames (seed
# kinematics, default 20,001), then for each N starts N viewers together and prints each
# one's frames per second of wall time (frames / its own run time, scene building
# included) and the total. Uses the binaries in $MBSTREAM_BUILD_DIR (default build/).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${MBSTREAM_BUILD_DIR:-build}
frames=${FRAMES:-20001}
counts=("$@")
[ ${#counts[@]} -eq 0 ] && counts=(1 10)
work=$(mktemp -d)
server_pid=
cleanup() {
  [ -n "$server_pid" ] && kill "$server_pid" 2>/dev/null
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

"$build/server/app/mbstream-server" --listen 127.0.0.1:0 --data "$work/data" \
  --max-subscribers 64 >"$work/server.log" 2>&1 &
server_pid=$!
for _ in $(seq 100); do grep -q "^listening on" "$work/server.log" && break; sleep 0.1; done
address=$(grep -m1 "^listening on " "$work/server.log" | cut -d' ' -f3)
interval=$(/usr/bin/python3 -c "print(20.0 / ($frames - 1))")
run=$("$build/client/mbstream" --server "$address" run irb1600 \
  --spec models/irb1600/seed-run.json --output-interval "$interval" --realtime 0 --watch \
  2>/dev/null | head -1)
echo "run $run: $frames frames; load $(cut -d' ' -f1-3 /proc/loadavg)"
for n in "${counts[@]}"; do
  start=$(date +%s.%N)
  for i in $(seq "$n"); do
    ( s=$(date +%s.%N)
      xvfb-run -a "$build/viewer/app/mbstream-viewer" --server "$address" --run "$run" \
        --speed 0 --offscreen --size 320x240 --no-hud >"$work/viewer-$n-$i.log" 2>&1
      e=$(date +%s.%N)
      echo "$s $e" >"$work/time-$n-$i" ) &
  done
  wait $(jobs -p | grep -v "^$server_pid$") 2>/dev/null || true
  end=$(date +%s.%N)
  /usr/bin/python3 - "$work" "$n" "$frames" "$start" "$end" <<'PY'
import glob, sys
work, n, frames, start, end = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5])
rates = []
for i in range(1, n + 1):
    s, e = map(float, open(f"{work}/time-{n}-{i}").read().split())
    log = open(f"{work}/viewer-{n}-{i}.log").read()
    ok = f"{frames} frames, {frames} probe reports" in log
    rates.append((frames / (e - s), ok))
per = sorted(r for r, _ in rates)
print(f"{n:2d} viewers: per viewer {per[len(per) // 2]:.0f} frames/s (median; min {per[0]:.0f}, "
      f"max {per[-1]:.0f}), total {n * frames / (end - start):.0f} frames/s over "
      f"{end - start:.1f} s; every frame answered: {all(ok for _, ok in rates)}")
PY
done
