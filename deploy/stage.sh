#!/usr/bin/env bash
# Stages the build context of the docker-compose demo's images (deploy/Dockerfile): the three
# programs that scripts/test.sh (or demo.sh) built on this Debian 12 host, stripped, the Debian
# packages holding the libraries each loads (deploy/docker/runtime-packages.sh), the IRB 1600
# model, demo-client.sh, and the web page with the pinned three.js that scripts/setup.sh
# installed on this host (`npm ci` in viewer/web): nothing is compiled and no npm registry is
# asked inside an image. The binaries match the image, which is Debian 12 too.
#
#   deploy/stage.sh [BUILD_DIR] [STAGE_DIR]      (defaults build/ and deploy/stage/, git-ignored)
#
# What the page needs of three.js (viewer/web/index.html's import map): three.module.min.js
# (build/) and OrbitControls (examples/jsm/controls/), with three's LICENSE.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/.." && pwd)
build=${1:-$root/build}
stage=${2:-$here/stage}
web=$root/viewer/web
three=$web/node_modules/three

for b in server/app/mbstream-server client/mbstream viewer/app/mbstream-viewer; do
  [ -x "$build/$b" ] || { echo "stage: $build/$b is missing; build it first (scripts/test.sh)" >&2; exit 1; }
done
[ -f "$three/build/three.module.min.js" ] && [ -d "$three/examples/jsm/controls" ] ||
  { echo "stage: $three is incomplete; scripts/setup.sh installs it (npm ci in viewer/web)" >&2; exit 1; }
pinned=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["packages"]["node_modules/three"]["version"])' \
  "$web/package-lock.json")
installed=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["version"])' "$three/package.json")
[ "$pinned" = "$installed" ] ||
  { echo "stage: viewer/web has three $installed, its lock file pins $pinned: run scripts/setup.sh" >&2; exit 1; }

rm -rf "$stage"
mkdir -p "$stage/bin" "$stage/models" "$stage/web/node_modules/three/examples/jsm"
for b in server/app/mbstream-server client/mbstream viewer/app/mbstream-viewer; do
  cp "$build/$b" "$stage/bin/"
done
strip "$stage"/bin/*
"$here/docker/runtime-packages.sh" "$stage/bin/mbstream-server" >"$stage/server.packages"
"$here/docker/runtime-packages.sh" "$stage/bin/mbstream" >"$stage/client.packages"
"$here/docker/runtime-packages.sh" "$stage/bin/mbstream-viewer" >"$stage/viewer.packages"
cp -r "$root/models/irb1600" "$stage/models/"
cp "$here/demo-client.sh" "$stage/"
cp "$web/index.html" "$web/page.js" "$web/page.css" "$stage/web/"
cp -r "$three/build" "$three/LICENSE" "$three/package.json" "$stage/web/node_modules/three/"
cp -r "$three/examples/jsm/controls" "$stage/web/node_modules/three/examples/jsm/"
cp "$here/Dockerfile" "$stage/Dockerfile"
echo "stage: $stage ($(du -sh "$stage" | cut -f1); three $installed)"
