#!/usr/bin/env bash
# What N web pages cost the viewer (issue 30: the VTK window's frame rate and the probe round
# trip unchanged within 5 % with 10 pages open at 20 Hz): one offscreen viewer (Xvfb) follows
# runs with --web 127.0.0.1:0; for each N, the seed run at real time (20 s, 20 frames/s) while
# bench/viewer/web_latency_bench --connect holds N pages on it. Prints, per N, the viewer's
# draws per second (as its frames report them), the probe round trip (probes.csv latency_us,
# median and p90) and the pages' posed -> read latency.
#
#   bench/web_pages_viewer.sh [N ...]     (default: 1 10; 0 = no page for 14 s, then one page
#                                          for 1 s reads the draw rate the viewer measured
#                                          over the second before it; interleave counts,
#                                          e.g. 0 10 0 10 0 10, for repetitions)
#
# Uses the binaries in $MBSTREAM_BUILD_DIR (default build/).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${MBSTREAM_BUILD_DIR:-build}
counts=("$@")
[ ${#counts[@]} -eq 0 ] && counts=(1 10)
work=$(mktemp -d)
pids=()
viewer_group=
cleanup() {
  [ -n "$viewer_group" ] && kill -- "-$viewer_group" 2>/dev/null
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

"$build/server/app/mbstream-server" --listen 127.0.0.1:0 --data "$work/data" >"$work/server.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do grep -q "^listening on" "$work/server.log" && break; sleep 0.1; done
address=$(grep -m1 "^listening on " "$work/server.log" | cut -d' ' -f3)
setsid xvfb-run -a "$build/viewer/app/mbstream-viewer" --server "$address" --follow --offscreen \
  --web 127.0.0.1:0 >"$work/viewer.log" 2>&1 &
viewer_group=$!  # its own process group (setsid): xvfb-run, Xvfb and the viewer
for _ in $(seq 300); do grep -q "^web on " "$work/viewer.log" && break; sleep 0.1; done
web=$(grep -m1 "^web on " "$work/viewer.log" | sed 's|^web on http://||; s|/$||')
for _ in $(seq 300); do grep -q "subscribed to" "$work/viewer.log" && break; sleep 0.1; done
echo "viewer on $web; load $(cut -d' ' -f1-3 /proc/loadavg)"
for n in "${counts[@]}"; do
  "$build/client/mbstream" --server "$address" run irb1600 --spec models/irb1600/seed-run.json \
    --realtime 1 --watch >"$work/client-$n.out" 2>&1 &
  client=$!
  sleep 2  # the run's scene is built: the pages then see its frames only
  if [ "$n" -gt 0 ]; then
    "$build/bench/viewer/web_latency_bench" --connect "$web" --pages "$n" --seconds 15
  else  # no page for 14 s; then one for 1 s reads the draw rate of the seconds before it
    sleep 14
    "$build/bench/viewer/web_latency_bench" --connect "$web" --pages 1 --seconds 1
  fi
  wait "$client"
  sleep 1  # late probe reports
  "$build/client/mbstream" --server "$address" result "$(head -n1 "$work/client-$n.out")" \
    --out "$work/final-$n" >/dev/null 2>&1 || true
  /usr/bin/python3 - "$work/final-$n/probes.csv" "$n" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
lat = sorted(float(r["latency_us"]) for r in rows)
print(f"{int(sys.argv[2]):3d} pages: probe round trip p50 {lat[len(lat) // 2]:.0f} us, "
      f"p90 {lat[int(0.9 * (len(lat) - 1))]:.0f} us over {len(lat)} probe reports")
PY
done
