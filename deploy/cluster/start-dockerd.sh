#!/usr/bin/env bash
# Starts Debian's Docker daemon (package docker.io) by hand where no init system runs it, and
# waits until it answers. Prints "dockerd: running" (or why not); exit 0 only when it answers.
# Used by the cluster's docker test (deploy/cluster/docker-test.sh) and by hand.
#
#   deploy/cluster/start-dockerd.sh [LOG_FILE]    (default /tmp/mbstream-dockerd.log)
#
# The daemon it starts keeps running; its process id is in LOG_FILE.pid (scripts/test.sh's
# docker stage stops it after the stage).
set -uo pipefail

log=${1:-/tmp/mbstream-dockerd.log}
if docker info >/dev/null 2>&1; then echo "dockerd: running"; exit 0; fi
command -v dockerd >/dev/null || { echo "dockerd: not installed (Debian package docker.io)"; exit 1; }
[ "$(id -u)" -eq 0 ] || { echo "dockerd: starting it needs root"; exit 1; }
nohup dockerd >"$log" 2>&1 &
echo $! >"$log.pid"
for _ in $(seq 1 100); do
  docker info >/dev/null 2>&1 && { echo "dockerd: running"; exit 0; }
  kill -0 $! 2>/dev/null || break
  sleep 0.2
done
echo "dockerd: did not start; last lines of $log:"
tail -n 5 "$log"
exit 1
