#!/usr/bin/env bash
# Stages the cluster images' build context in deploy/cluster/stage/ (git-ignored): the three
# programs from a Release build on this Debian 12 host, stripped, with the Debian packages
# holding the libraries each loads (deploy/docker/runtime-packages.sh), the IRB 1600 model and
# the cluster's scripts. Building from these instead of compiling inside Docker (as the
# demo's deploy/Dockerfile did before deploy/stage.sh) makes an image build take minutes on a
# 2-core machine instead of the better part of an hour; the binaries match the image, which is
# Debian 12 too.
#
#   deploy/cluster/stage.sh [BUILD_DIR]      (default build/)
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
stage=$here/stage
rm -rf "$stage"
mkdir -p "$stage/bin" "$stage/models"
for b in server/app/mbstream-server client/mbstream viewer/app/mbstream-viewer; do
  [ -x "$build/$b" ] || { echo "stage: $build/$b is missing; build it first" >&2; exit 1; }
  cp "$build/$b" "$stage/bin/"
done
strip "$stage"/bin/*
"$root/deploy/docker/runtime-packages.sh" "$stage/bin/mbstream-server" >"$stage/server.packages"
"$root/deploy/docker/runtime-packages.sh" "$stage/bin/mbstream" >"$stage/client.packages"
"$root/deploy/docker/runtime-packages.sh" "$stage/bin/mbstream-viewer" >"$stage/viewer.packages"
cp -r "$root/models/irb1600" "$stage/models/"
cp "$here/sweep-client.sh" "$here/haproxy-config.sh" "$here/haproxy.cfg.in" \
  "$here/postgres-entrypoint.sh" "$stage/"
echo "stage: $stage ($(du -sh "$stage" | cut -f1))"
