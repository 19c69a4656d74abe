#!/usr/bin/env bash
# The cluster's client, run as is by the compose `client` service and by the network-namespace
# test (netns.sh): submits the IRB 1600, starts a sweep of runs over the relative tolerance
# (joint space, BDF) through the load balancer, waits until every run has ended and checks
# that each one FINISHED.
#
#   sweep-client.sh MODEL_DIR SPEC.json [RUNS]       (RUNS default 30)
#
# The server (the load balancer), CA and token come from MBSTREAM_SERVER, MBSTREAM_CA and
# MBSTREAM_TOKEN_FILE (read by the CLI); MBSTREAM_CLI names the CLI (default `mbstream`);
# MBSTREAM_SWEEP_DURATION the simulated seconds per run (default 2). Prints one run id per
# line on stdout, progress on stderr; exit 0 only when every run finished.
set -euo pipefail

if [ $# -lt 2 ] || [ $# -gt 3 ]; then
  echo "usage: sweep-client.sh MODEL_DIR SPEC.json [RUNS]" >&2
  exit 2
fi
model_dir=$1 spec=$2 count=${3:-30}
cli=${MBSTREAM_CLI:-mbstream}
duration=${MBSTREAM_SWEEP_DURATION:-2}

model=$("$cli" submit "$model_dir")
echo "sweep-client: submitted $model_dir as model $model" >&2
ids=()
for i in $(seq 0 $((count - 1))); do
  # rtol from 1e-3 to 1e-8, log-spaced; atol a hundredth of it.
  rtol=$(awk -v i="$i" -v n="$count" 'BEGIN { printf "%.3g", 10 ^ (-3 - 5 * i / (n > 1 ? n - 1 : 1)) }')
  atol=$(awk -v r="$rtol" 'BEGIN { printf "%.3g", r / 100 }')
  ids+=("$("$cli" run "$model" --spec "$spec" --duration "$duration" --formulation joint \
    --method bdf --rtol "$rtol" --atol "$atol" --realtime 0)")
done
echo "sweep-client: started ${#ids[@]} runs (rtol 1e-3 .. 1e-8)" >&2

# Wait until none of them is QUEUED or RUNNING (ListRuns reads the shared store: any replica
# answers for every run).
while true; do
  listing=$("$cli" runs)
  pending=0 finished=0
  for id in "${ids[@]}"; do
    state=$(awk -v id="$id" '$1 == id { print $3 }' <<<"$listing")
    case "$state" in
      QUEUED|RUNNING|"") pending=$((pending + 1)) ;;
      FINISHED) finished=$((finished + 1)) ;;
    esac
  done
  [ "$pending" -eq 0 ] && break
  sleep 0.5
done
printf '%s\n' "${ids[@]}"
echo "sweep-client: $finished of ${#ids[@]} runs FINISHED" >&2
if [ "$finished" -ne "${#ids[@]}" ]; then
  for id in "${ids[@]}"; do
    awk -v id="$id" '$1 == id && $3 != "FINISHED" { print "sweep-client: " $0 }' <<<"$listing" >&2
  done
  exit 1
fi
