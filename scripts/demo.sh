#!/usr/bin/env bash
# The IRB 1600 demo on this machine: the simulation server, an offscreen viewer (Xvfb) and
# the CLI run the seed experiment (20 s of sine-driven joints, output every 50 ms).
#
#   scripts/demo.sh [--quick] [--no-build] [--out DIR]
#
# Installs what is missing, builds, starts everything, and leaves in out/demo/: robot.ogv,
# snapshots/*.png, results/ (joints.csv, tcp.csv, probes.csv, stats.json ...),
# tcp_vs_probe.png and the logs. Second act: seed-servo with BDF and with fixed-step
# semi-implicit Euler (h = 1e-4 s, its largest stable step: docs/accuracy.md), replayed side
# by side with Euler as the ghost: compare_bdf_euler.ogv, compare_bdf_euler.png (the TCP
# distance against time), compare/ (both results). --quick runs both acts at 10x real time
# instead of real time; --no-build uses the binaries already in build/.
set -euo pipefail
cd "$(dirname "$0")/.."

quick=0 build=1 out=out/demo
while [ $# -gt 0 ]; do
  case "$1" in
    --quick) quick=1 ;;
    --no-build) build=0 ;;
    --out) out="$2"; shift ;;
    *) echo "usage: scripts/demo.sh [--quick] [--no-build] [--out DIR]" >&2; exit 2 ;;
  esac
  shift
done
build_dir=${MBSTREAM_BUILD_DIR:-build}
server=$build_dir/server/app/mbstream-server
viewer=$build_dir/viewer/app/mbstream-viewer
cli=$build_dir/client/mbstream

if [ $build -eq 1 ]; then
  scripts/setup.sh
  # The configuration and compiler cache of scripts/test.sh: a test.sh after the demo
  # compiles only what the demo did not need.
  source scripts/build_env.sh
  mbstream_configure "$build_dir" >/dev/null
  mbstream_build "$build_dir" mbstream-server mbstream-viewer mbstream
fi

rm -rf "$out"
mkdir -p "$out"
data=$(mktemp -d)
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
  rm -rf "$data"
}
trap cleanup EXIT

# Waits until FILE has a line matching PATTERN (or fails after 30 s).
wait_for() {
  for _ in $(seq 300); do
    grep -q "$2" "$1" 2>/dev/null && return 0
    sleep 0.1
  done
  echo "demo: timed out waiting for '$2' in $1" >&2
  cat "$1" >&2
  exit 1
}

echo "demo: starting the simulation server"
"$server" --listen 127.0.0.1:0 --data "$data/store" >"$out/server.log" 2>&1 &
pids+=($!)
wait_for "$out/server.log" "^listening on "
address=$(grep -m1 "^listening on " "$out/server.log" | cut -d' ' -f3)

echo "demo: starting the offscreen viewer (Xvfb) on $address"
XVFB_SCREEN=1024x768x24 scripts/with-xvfb.sh "$viewer" --server "$address" --follow \
  --exit-after-runs 1 --offscreen --size 640x480 --record "$out/robot.ogv" \
  --snapshots "$out/snapshots" --snapshot-every 40 >"$out/viewer.log" 2>&1 &
viewer_pid=$!
pids+=($viewer_pid)
wait_for "$out/viewer.log" "subscribed to"

realtime=1
[ $quick -eq 1 ] && realtime=10
echo "demo: submitting models/irb1600 and running the seed experiment at ${realtime}x real time"
"$cli" --server "$address" submit models/irb1600
run=$("$cli" --server "$address" run irb1600 --spec models/irb1600/seed-run.json \
  --realtime "$realtime" --watch --out "$out/results")
wait "$viewer_pid"  # it exits after the run ended and its last probes went out
# Fetch again: now with every probe report the viewer sent.
"$cli" --server "$address" result "$run" --out "$out/results"
/usr/bin/python3 scripts/plot_tcp_vs_probe.py --results "$out/results" --out "$out/tcp_vs_probe.png"

echo "demo: second act: seed-servo with BDF and with semi-implicit Euler (h = 1e-4 s), compared"
bdf=$("$cli" --server "$address" run irb1600 --spec models/irb1600/seed-servo.json \
  --realtime 0 --watch --out "$out/compare/bdf")
# Euler's own error indicators may call its result untrusted (exit 4): that is the point.
euler=$("$cli" --server "$address" run irb1600 --spec models/irb1600/seed-servo.json \
  --method euler --step 1e-4 --realtime 0 --watch --accept-untrusted --out "$out/compare/euler")
XVFB_SCREEN=1024x768x24 scripts/with-xvfb.sh "$viewer" --server "$address" --run "$bdf" \
  --compare "$euler" --speed "$realtime" --offscreen --size 640x480 \
  --record "$out/compare_bdf_euler.ogv" >"$out/compare_viewer.log" 2>&1
grep "compare $bdf with ghost" "$out/compare_viewer.log"
/usr/bin/python3 scripts/plot_compare.py --run "$out/compare/bdf" --ghost "$out/compare/euler" \
  --label-run "BDF (rtol 1e-6)" --label-ghost "semi-implicit Euler, h = 1e-4 s" \
  --out "$out/compare_bdf_euler.png"

echo "demo: done. In $out/:"
echo "  robot.ogv            the viewer's recording"
echo "  snapshots/           PNG snapshots"
echo "  results/             joints.csv velocities.csv tcp.csv probes.csv stats.json"
echo "  tcp_vs_probe.png     simulated TCP and the viewer's probe against time"
echo "  compare_bdf_euler.ogv  BDF with semi-implicit Euler as its ghost (second act)"
echo "  compare_bdf_euler.png  their TCP distance against time"
