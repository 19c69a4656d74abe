#!/bin/bash
# The control round trip with the server in another process (issue 45's p50 goal, as a user's
# controller has it): starts mbstream-server and the bare echo (`stream_bench --serve-echo`)
# on loopback, each in its own process, then runs the out-of-process pair of stream_bench
# (BM_BarePingPongOutOfProcess, BM_ControlRoundTripOutOfProcess) ROUNDS times, interleaved,
# and prints each run's p50 and p99 and the medians' ratio.
#   bench/control_process.sh [BUILD_DIR] [ROUNDS]
set -euo pipefail
build=${1:-build}
rounds=${2:-5}
work=$(mktemp -d)
cleanup() {
  [ -n "${server_pid:-}" ] && kill "$server_pid" 2>/dev/null || true
  [ -n "${echo_pid:-}" ] && kill "$echo_pid" 2>/dev/null || true
  wait 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

"$build/server/app/mbstream-server" --listen 127.0.0.1:0 --data "$work/data" \
  --models models >"$work/server.log" 2>&1 &
server_pid=$!
for _ in $(seq 1 600); do  # until it says where it listens (a log line, not a sleep's guess)
  server=$(grep -o 'listening on [^ ]*' "$work/server.log" | head -1 | cut -d' ' -f3) || true
  [ -n "$server" ] && break
  kill -0 "$server_pid" || { cat "$work/server.log"; exit 1; }
  sleep 0.1
done
mkfifo "$work/echo_in"
"$build/bench/stream_bench" --serve-echo <"$work/echo_in" >"$work/echo.out" &
echo_pid=$!
exec 3>"$work/echo_in"  # the echo serves until this closes
for _ in $(seq 1 600); do
  echo_address=$(head -1 "$work/echo.out" 2>/dev/null) || true
  [ -n "$echo_address" ] && break
  sleep 0.1
done
echo "server $server (pid $server_pid), echo $echo_address (pid $echo_pid); $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)"
export MBSTREAM_BENCH_SERVER=$server MBSTREAM_BENCH_ECHO=$echo_address
for round in $(seq 1 "$rounds"); do
  for bench in BM_BarePingPongOutOfProcess BM_ControlRoundTripOutOfProcess; do
    "$build/bench/stream_bench" --benchmark_filter="^$bench/" --benchmark_format=csv 2>/dev/null |
      python3 -c '
import csv, sys
rows = [r for r in csv.reader(sys.stdin)]
head = rows.index(next(r for r in rows if r and r[0] == "name"))
names = rows[head]
for r in rows[head + 1:]:
    d = dict(zip(names, r))
    print("round '"$round"'", d["name"], "p50_us", d.get("p50_us"), "p99_us", d.get("p99_us"),
          "x_real_time", d.get("x_real_time", ""))'
  done
done | tee "$work/rounds.txt"
python3 - "$work/rounds.txt" <<'PY'
import statistics, sys
p50 = {}
for line in open(sys.argv[1]):
    f = line.split()
    p50.setdefault(f[2].split("/")[0], []).append(float(f[4]))
echo = statistics.median(p50["BM_BarePingPongOutOfProcess"])
control = statistics.median(p50["BM_ControlRoundTripOutOfProcess"])
print(f"median p50: echo {echo:.1f} us, control {control:.1f} us, ratio {control / echo:.2f} x")
PY
