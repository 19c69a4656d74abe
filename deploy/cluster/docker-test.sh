#!/usr/bin/env bash
# The cluster in Docker (docker-compose.yml), run for real: starts Debian's Docker daemon if
# none answers (start-dockerd.sh), makes the debootstrap base image if it is missing
# (make-base-image.sh), stages the binaries of BUILD_DIR (stage.sh), builds the images
# (`docker build --network host`), brings up PostgreSQL, three replicas, HAProxy and the
# viewer, runs the client's sweep of 30 runs, and checks: every run FINISHED, each replica
# finished some and together all (their /metrics), the viewer answered every frame of the run
# it followed; as deploy/cluster/netns.sh: a viewer following server1 directly answered every
# frame of a run integrated on another replica, and a replica killed (SIGKILL) during a run has
# that run INTERRUPTED (--lease-timeout-s 5) while the other replicas' runs FINISH.
# Everything is brought down (volumes too) on every exit path.
#
#   deploy/cluster/docker-test.sh [--images-only] [BUILD_DIR]      (default build/)
#
# --images-only: make the base image and build the images, then stop (scripts/test.sh --ci builds
# them beside the sanitizer stages, so that its docker stage finds them in the daemon's cache).
#
# Exits 77 (skipped, with the reason) when no Docker daemon can be started, or the base image
# is missing and cannot be made (no debootstrap, not root). CI installs no Docker: there the
# ctest deploy_cluster_docker is skipped.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
images_only=0
if [ "${1:-}" = --images-only ]; then images_only=1; shift; fi
build=${1:-$root/build}
log() { echo "cluster-docker: $*"; }
skip() { echo "cluster-docker: SKIPPED: $*"; exit 77; }
fail() { echo "cluster-docker: FAIL: $*" >&2; exit 1; }

command -v docker >/dev/null || skip "no docker command (Debian package docker.io)"
compose=(docker-compose)
command -v docker-compose >/dev/null || { docker compose version >/dev/null 2>&1 && compose=(docker compose); } ||
  skip "no docker-compose (Debian package docker-compose)"
"$here/start-dockerd.sh" >/tmp/mbstream-start-dockerd.out 2>&1 ||
  skip "no Docker daemon answers and none could be started: $(tail -n1 /tmp/mbstream-start-dockerd.out)"
if ! docker image inspect mbstream-base:bookworm >/dev/null 2>&1; then
  [ "$(id -u)" -eq 0 ] && command -v debootstrap >/dev/null ||
    skip "the base image mbstream-base:bookworm is missing and cannot be made here (needs root and debootstrap)"
  "$here/make-base-image.sh" || fail "make-base-image.sh"
fi

"$here/stage.sh" "$build" >/dev/null
"$here/make-secrets.sh" --force >/dev/null
project=mbscluster$$
dc() { "${compose[@]}" -p "$project" -f "$here/docker-compose.yml" "$@"; }
cleanup() {
  local rc=$?
  set +e
  trap - EXIT INT TERM
  [ "$rc" -ne 0 ] && dc logs --no-color --tail 20 >&2
  dc down -v --remove-orphans >/dev/null 2>&1
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

started=$(date +%s)
dc build -q >/dev/null 2>&1 || dc build || fail "building the images"
log "images built in $(($(date +%s) - started)) s"
[ "$images_only" = 1 ] && exit 0
dc up -d postgres server1 server2 server3 lb viewer >/dev/null 2>&1 || dc up -d postgres server1 server2 server3 lb viewer ||
  fail "bringing the cluster up"
log "up: postgres, server1-3, lb (HAProxy), viewer"
cli() {  # cli SERVER ARGS...: the CLI in a client container against SERVER (host:port)
  local server=$1
  shift
  dc run --rm --no-deps -e MBSTREAM_SERVER="$server" --entrypoint mbstream client "$@" 2>/dev/null
}
owner_of() {  # owner_of RUN: the service (server1..3) whose log says it claimed RUN
  local s logs
  for s in server1 server2 server3; do
    # The log read whole first: `dc logs | grep -q` fails under pipefail when grep's early exit
    # makes the writer die of SIGPIPE.
    logs=$(dc logs --no-color "$s" 2>&1 || true)
    grep -q "run $1 claimed by replica" <<<"$logs" && { echo "$s"; return; }
  done
  echo none
}
state_of() {  # state_of SERVER RUN
  cli "$1" runs | awk -v id="$2" '$1 == id { print $3 }'
}
seed=/opt/mbstream/models/irb1600/seed-run.json

# A viewer following server1 directly; a run started on server2 (integrated there, unless
# server1 wins the claim: then again, at most 3 times); server1 relays it.
extra=0
for attempt in 1 2 3; do
  dc run -d --no-deps --name "$project-direct-viewer-$attempt" viewer xvfb-run -a mbstream-viewer \
    --server server1:50051 --follow --offscreen --ca /run/secrets/ca \
    --token-file /run/secrets/viewer_token --exit-after-runs 1 >/dev/null
  for _ in $(seq 1 200); do
    grep -q "subscribed to" <<<"$(docker logs "$project-direct-viewer-$attempt" 2>&1 || true)" && break
    sleep 0.1
  done
  shown=$(cli server2:50051 run irb1600 --spec "$seed" --duration 2 --realtime 1)
  extra=$((extra + 1))
  [ "$(timeout 60 docker wait "$project-direct-viewer-$attempt")" = 0 ] ||
    fail "the viewer following server1 did not exit 0 after run $shown"
  owner=$(owner_of "$shown")
  direct_line=$(docker logs "$project-direct-viewer-$attempt" 2>&1 | grep -m1 -o 'viewer done: .*' || true)
  docker rm -f "$project-direct-viewer-$attempt" >/dev/null 2>&1
  [ "$owner" != server1 ] && break
done
[ "$owner" != server1 ] && [ "$owner" != none ] || fail "run $shown was not integrated on another replica than server1"
read -r frames probes < <(sed -E 's/.*: ([0-9]+) frames, ([0-9]+) probe reports.*/\1 \2/' <<<"$direct_line")
[[ "$direct_line" == *"last run $shown:"* ]] && [ "${frames:-0}" -gt 0 ] && [ "$frames" = "$probes" ] ||
  fail "the viewer on server1 did not answer every frame of run $shown ($owner): '$direct_line'"
log "viewer on server1: run $shown integrated on $owner: $frames frames, $probes probe reports"

started=$(date +%s.%N)
dc run --rm client >"/tmp/$project.client.out" 2>"/tmp/$project.client.err" ||
  { cat "/tmp/$project.client.err" >&2; fail "the sweep client failed"; }
elapsed=$(awk -v a="$started" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
sed 's/^/  client: /' "/tmp/$project.client.err"
runs=$(wc -l <"/tmp/$project.client.out")
rm -f "/tmp/$project.client.out" "/tmp/$project.client.err"
[ "$runs" -eq 30 ] || fail "the client printed $runs run ids, expected 30"

total=0 spread=""
for s in server1 server2 server3; do
  n=$(dc run --rm --no-deps --entrypoint curl client -sf "http://$s:9464/metrics" |
    awk '$1 == "mbstream_runs_ended_total{state=\"finished\"}" { print $2 }')
  [ -n "$n" ] || fail "$s served no metrics"
  spread+="${spread:+, }$s $n"
  total=$((total + n))
  [ "$n" -ge 1 ] || fail "$s finished no run of the sweep ($spread)"
done
[ "$total" -eq $((30 + extra)) ] ||
  fail "the replicas finished $total runs together, the sweep had 30 (and the viewer's $extra)"

viewer=$(dc ps -q viewer)
[ "$(timeout 30 docker wait "$viewer")" = 0 ] || fail "the viewer did not exit 0 after its run"
done_line=$(docker logs "$viewer" 2>&1 | grep -m1 -o 'viewer done: .*' || true)
read -r frames probes < <(sed -E 's/.*: ([0-9]+) frames, ([0-9]+) probe reports.*/\1 \2/' <<<"$done_line")
[ -n "$done_line" ] && [ "${frames:-0}" -gt 0 ] && [ "$frames" = "$probes" ] ||
  fail "the viewer did not answer every frame of its run: '$done_line'"

# A replica killed during a run: four paced runs (40 s) through the balancer, the first's
# replica killed once all run.
# One client container starts all four (a container start takes seconds here).
mapfile -t kill_ids < <(dc run --rm --no-deps -e MBSTREAM_SERVER=lb:50051 --entrypoint sh client -c \
  "for i in 1 2 3 4; do mbstream run irb1600 --spec $seed --duration 40 --realtime 1; done" 2>/dev/null)
[ "${#kill_ids[@]}" -eq 4 ] || fail "starting the four runs to kill a replica under failed"
for _ in $(seq 1 10); do
  listing=$(cli lb:50051 runs)
  running=0
  for r in "${kill_ids[@]}"; do
    [ "$(awk -v id="$r" '$1 == id { print $3 }' <<<"$listing")" = RUNNING ] && running=$((running + 1))
  done
  [ "$running" -eq 4 ] && break
done
[ "$running" -eq 4 ] || fail "the four runs to kill a replica under did not all run"
victim=$(owner_of "${kill_ids[0]}")
[ "$victim" != none ] || fail "no replica says it claimed run ${kill_ids[0]}"
survivor=server1
[ "$victim" = server1 ] && survivor=server2
docker kill -s KILL "$(dc ps -q "$victim")" >/dev/null
killed_at=$(date +%s.%N)
while [ "$(state_of "$survivor:50051" "${kill_ids[0]}")" = RUNNING ]; do :; done
marked=$(awk -v a="$killed_at" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
final=$(state_of "$survivor:50051" "${kill_ids[0]}")
[ "$final" = INTERRUPTED ] || fail "run ${kill_ids[0]} of the killed $victim is $final, not INTERRUPTED"
others=0
for r in "${kill_ids[@]:1}"; do
  while :; do
    state=$(state_of "$survivor:50051" "$r")
    case "$state" in QUEUED|RUNNING|"") ;; *) break ;; esac
  done
  if [ "$(owner_of "$r")" = "$victim" ]; then
    [ "$state" = INTERRUPTED ] || fail "run $r of the killed $victim is $state"
  else
    others=$((others + 1))
    [ "$state" = FINISHED ] || fail "run $r of $(owner_of "$r") is $state after $victim was killed"
  fi
done
[ "$others" -ge 1 ] || fail "all four runs were on $victim: nothing shows the others unaffected"

echo "cluster-docker: ---- summary ----"
echo "cluster-docker: sweep: 30 runs FINISHED in $elapsed s (client container start included)"
echo "cluster-docker: spread: $spread"
echo "cluster-docker: viewer: $done_line"
echo "cluster-docker: viewer on server1: run $shown integrated on $owner: $frames frames, $probes probe reports"
echo "cluster-docker: kill: $victim killed during run ${kill_ids[0]}: INTERRUPTED ${marked} s later (container starts included); $others runs of other replicas FINISHED"
echo "cluster-docker: PASS"
