#!/usr/bin/env bash
# The docker-compose demo (deploy/docker-compose.yml) run for real: starts Debian's Docker
# daemon if none answers (cluster/start-dockerd.sh), makes the debootstrap base image if it is
# missing (cluster/make-base-image.sh; kept for the next run), stages the programs of BUILD_DIR
# with the web page's pinned three.js (stage.sh), builds the three images, brings up the server
# and the viewer, fetches the page and its three.js from the viewer over HTTPS, runs the client
# (submit the IRB 1600, the seed run at real time, download), and checks: the client exited 0,
# the viewer answered every frame of the run and exited 0, the results, the video and the
# snapshots are in the output volume. Everything of its own (containers, network, volumes,
# secrets, context) goes on every exit path; the images stay (the next build reuses them).
# Host ports are any free ones, and the secrets, context and volume are its own, so it runs
# beside a demo of your own.
#
#   deploy/docker-test.sh [--images-only] [BUILD_DIR]      (default build/)
#
# --images-only: make the base image and build the images, then stop (scripts/test.sh --ci builds
# them beside the sanitizer stages, so that its docker stage finds them in the daemon's cache).
#
# Exits 77 (skipped, with the reason) when no Docker daemon can be started, or the base image
# is missing and cannot be made (no debootstrap, not root). scripts/test.sh --ci runs it in its
# docker stage (docs/reliability.md).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/.." && pwd)
images_only=0
if [ "${1:-}" = --images-only ]; then images_only=1; shift; fi
build=${1:-$root/build}
log() { echo "compose-docker: $*"; }
skip() { echo "compose-docker: SKIPPED: $*"; exit 77; }
fail() { echo "compose-docker: FAIL: $*" >&2; exit 1; }

command -v docker >/dev/null || skip "no docker command (Debian package docker.io)"
compose=(docker-compose)
command -v docker-compose >/dev/null || { docker compose version >/dev/null 2>&1 && compose=(docker compose); } ||
  skip "no docker-compose (Debian package docker-compose)"
"$here/cluster/start-dockerd.sh" >/tmp/mbstream-start-dockerd.out 2>&1 ||
  skip "no Docker daemon answers and none could be started: $(tail -n1 /tmp/mbstream-start-dockerd.out)"
started=$(date +%s)
if ! docker image inspect mbstream-base:bookworm >/dev/null 2>&1; then
  [ "$(id -u)" -eq 0 ] && command -v debootstrap >/dev/null ||
    skip "the base image mbstream-base:bookworm is missing and cannot be made here (needs root and debootstrap)"
  "$here/cluster/make-base-image.sh" || fail "make-base-image.sh"
  log "base image made in $(($(date +%s) - started)) s"
fi

work=$(mktemp -d /tmp/mbstream-compose-test.XXXXXX)
project=mbsdemo$$
export MBSTREAM_DEMO_STAGE=$work/stage MBSTREAM_DEMO_SECRETS=$work/secrets
export MBSTREAM_DEMO_OUT=$project-out MBSTREAM_DEMO_PORT="" MBSTREAM_DEMO_WEB_PORT=""
dc() { "${compose[@]}" -p "$project" -f "$here/docker-compose.yml" "$@"; }
cleanup() {
  local rc=$?
  set +e
  trap - EXIT INT TERM
  [ "$rc" -ne 0 ] && dc logs --no-color --tail 30 >&2
  dc down -v --remove-orphans >/dev/null 2>&1
  docker volume rm "$MBSTREAM_DEMO_OUT" >/dev/null 2>&1
  rm -rf "$work"
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

"$here/stage.sh" "$build" "$work/stage" >/dev/null
"$here/make-secrets.sh" "$work/secrets" >/dev/null

started=$(date +%s)
dc build -q >/dev/null 2>&1 || dc build || fail "building the images"
log "images built in $(($(date +%s) - started)) s"
[ "$images_only" = 1 ] && exit 0
dc up -d server viewer >/dev/null 2>&1 || dc up -d server viewer || fail "bringing up the server and the viewer"

# The page and the three.js it imports, served by the viewer from its image (no npm there).
web=$(dc port viewer 8443 | sed 's/.*://')
[ -n "$web" ] || fail "the viewer's web port is not published"
for _ in $(seq 1 100); do
  curl -sf --cacert "$work/secrets/ca.pem" -o /dev/null "https://localhost:$web/" && break
  sleep 0.2
done
for path in / /page.js /three/build/three.module.min.js /three/examples/jsm/controls/OrbitControls.js; do
  code=$(curl -s --cacert "$work/secrets/ca.pem" -o "$work/page" -w '%{http_code}' "https://localhost:$web$path")
  [ "$code" = 200 ] && [ -s "$work/page" ] || fail "the viewer's page gave $code for $path"
done
log "page: index.html, page.js, three.module.min.js and OrbitControls.js over HTTPS (port $web)"

started=$(date +%s)
dc run --rm client >"$work/client.out" 2>&1 || { cat "$work/client.out" >&2; fail "the client failed"; }
log "client: exited 0 after $(($(date +%s) - started)) s: $(grep -m1 -o 'FINISHED: [^,]*' "$work/client.out" || echo '?')"
grep -q "FINISHED" "$work/client.out" || { cat "$work/client.out" >&2; fail "the client's run did not finish"; }

viewer=$(dc ps -q viewer)
[ "$(timeout 60 docker wait "$viewer")" = 0 ] || fail "the viewer did not exit 0 after its run"
done_line=$(docker logs "$viewer" 2>&1 | grep -m1 -o 'viewer done: .*' || true)
read -r frames probes < <(sed -E 's/.*: ([0-9]+) frames, ([0-9]+) probe reports.*/\1 \2/' <<<"$done_line")
[ -n "$done_line" ] && [ "${frames:-0}" -gt 0 ] && [ "$frames" = "$probes" ] ||
  fail "the viewer did not answer every frame of the run: '$done_line'"
log "viewer: $done_line"

listing=$(dc run --rm --no-deps --entrypoint sh client -c \
  'cd /out && ls results && test -s robot.ogv && echo video && ls snapshots | head -n 1' 2>/dev/null)
for f in joints.csv velocities.csv tcp.csv stats.json video; do
  grep -qx "$f" <<<"$listing" || fail "the output volume has no $f: $(tr '\n' ' ' <<<"$listing")"
done
grep -q '\.png$' <<<"$listing" || fail "the output volume has no snapshot"
log "output volume: results/ (joints, velocities, tcp, stats), robot.ogv, snapshots/"
log "PASS"
