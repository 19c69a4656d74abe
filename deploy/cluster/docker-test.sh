#!/usr/bin/env bash
# The cluster in Docker (docker-compose.yml), run for real: starts Debian's Docker daemon if
# none answers (start-dockerd.sh), makes the debootstrap base image if it is missing
# (make-base-image.sh), stages the binaries of BUILD_DIR (stage.sh), builds the images
# (`docker build --network host`), brings up PostgreSQL, three replicas, HAProxy and the
# viewer, runs the client's sweep of 30 runs, and checks: every run FINISHED, each replica
# finished some and together all (their /metrics), the viewer answered every frame of the run
# it followed. Everything is brought down (volumes too) on every exit path.
#
#   deploy/cluster/docker-test.sh [BUILD_DIR]      (default build/)
#
# Exits 77 (skipped, with the reason) when no Docker daemon can be started, or the base image
# is missing and cannot be made (no debootstrap, not root). CI installs no Docker: there the
# ctest deploy_cluster_docker is skipped.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
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
dc up -d postgres server1 server2 server3 lb viewer >/dev/null 2>&1 || dc up -d postgres server1 server2 server3 lb viewer ||
  fail "bringing the cluster up"
log "up: postgres, server1-3, lb (HAProxy), viewer"
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
[ "$total" -eq 30 ] || fail "the replicas finished $total runs together, the sweep had 30"

viewer=$(dc ps -q viewer)
[ "$(timeout 30 docker wait "$viewer")" = 0 ] || fail "the viewer did not exit 0 after its run"
done_line=$(docker logs "$viewer" 2>&1 | grep -m1 -o 'viewer done: .*' || true)
read -r frames probes < <(sed -E 's/.*: ([0-9]+) frames, ([0-9]+) probe reports.*/\1 \2/' <<<"$done_line")
[ -n "$done_line" ] && [ "${frames:-0}" -gt 0 ] && [ "$frames" = "$probes" ] ||
  fail "the viewer did not answer every frame of its run: '$done_line'"

echo "cluster-docker: ---- summary ----"
echo "cluster-docker: sweep: 30 runs FINISHED in $elapsed s (client container start included)"
echo "cluster-docker: spread: $spread"
echo "cluster-docker: viewer: $done_line"
echo "cluster-docker: PASS"
