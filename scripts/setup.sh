#!/usr/bin/env bash
# Installs every Debian package mbstream needs to build and test (idempotent).
# Starts from a minimal Debian bookworm with only git; quiet when everything is present.
# Then builds the optimised SUNDIALS (scripts/build_sundials.sh) unless it is cached already.
#   scripts/setup.sh --docker   also Debian's Docker daemon and debootstrap (the docker stage of
#                               scripts/test.sh --ci: deploy/docker-test.sh)
#   scripts/setup.sh --peers    also DART 6.12 (Debian's libdart-dev: about 100 packages with all
#                               of Boost, so not by default), the third engine of
#                               bench/contact_peers (docs/accuracy.md, "Contact beside MuJoCo and
#                               DART"); CMake builds its runs when it finds DART (reconfigure)
# The options combine (setup.sh --docker --peers).
set -euo pipefail
DOCKER=0
PEERS=0
for option in "$@"; do
  case "$option" in
    --docker) DOCKER=1 ;;
    --peers) PEERS=1 ;;
    *)
      echo "setup: unknown option $option (known: --docker, --peers)" >&2
      exit 2
      ;;
  esac
done

PACKAGES=(
  # toolchain
  build-essential g++ cmake ninja-build ccache pkg-config git clang-format
  lld  # the linker CMake picks when present (cmake/MbstreamCompilerSettings.cmake)
  # core numerics
  libeigen3-dev libsundials-dev libsuitesparse-dev
  # contact (server/contact): FCL narrow and broad phase, with libccd; qhull for the convex
  # hulls of collision meshes (server/parse/convex_hull.h)
  libfcl-dev libccd-dev libqhull-dev
  # model import, logging, command line, persistence
  liburdfdom-dev libsdformat-dev libsimbody-dev libspdlog-dev libfmt-dev libcli11-dev libsqlite3-dev nlohmann-json3-dev
  # the shared store for several servers (--store postgresql://...); the tests start their own
  libpqxx-dev postgresql
  # the load balancer of the cluster test (deploy/cluster/netns.sh: HTTP/2 to the replicas)
  haproxy
  # wire contract
  libgrpc++-dev libprotobuf-dev protobuf-compiler protobuf-compiler-grpc libssl-dev openssl
  # fuzzing (fuzz/): clang 14 and its libFuzzer + sanitizer runtimes
  clang libclang-rt-14-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # a peer for the cross-checks of free bodies and ball joints (tests/server/free: MuJoCo's
  # forward dynamics at random states)
  libmujoco-dev
  # viewer and headless rendering
  libvtk9-dev xvfb xauth
  libassimp-dev  # viewer meshes and the server's collision meshes: Collada, OBJ, STL, glTF, PLY
  dart-doc  # a published robot with textured Collada meshes (the Barrett WAM) for WebViewTest
  # mbstream-viewer --web: Boost.Beast (HTTP, WebSocket); node for `npm ci` in viewer/web
  # (three.js, served to the pages; playwright-core for the test), chromium for the test
  libboost-dev nodejs chromium
  # MCAP export (server/mcap): zstd and lz4 chunks, zlib for the CRCs
  libzstd-dev liblz4-dev zlib1g-dev
  # python client and charts (Debian's, for /usr/bin/python3); installing the package
  # (client/python: pip install --no-build-isolation --no-deps) needs setuptools, pip, venv;
  # tqdm (progress bars) and pandas (Result.to_pandas) are optional, here so tests cover them;
  # mypy checks the package's type hints
  python3 python3-grpcio python3-protobuf python3-numpy python3-matplotlib
  python3-setuptools python3-pip python3-venv python3-tqdm python3-pandas python3-mypy
  # deploy/: validates the docker-compose demo (docker-compose config; no engine needed)
  docker-compose
  # deploy/multihost: network namespaces (ip, ss)
  iproute2
  # commands the tests and deploy scripts run (checked below): curl (deploy/cluster/netns.sh),
  # ps/pkill (tests/e2e), runuser (PostgreSQL as a non-root user), timeout
  curl procps util-linux coreutils
)

if [ "$DOCKER" = 1 ]; then
  # The compose demo and the cluster run for real (label docker): a daemon started by hand
  # (deploy/cluster/start-dockerd.sh), the base image made by debootstrap (make-base-image.sh).
  PACKAGES+=(docker.io debootstrap)
fi

# Every command a script or test runs, with the package that provides it: after the install
# each must be found, so a missing install step fails here, by name, and not in a test.
COMMANDS=(
  curl:curl ip:iproute2 ss:iproute2 ps:procps pkill:procps runuser:util-linux timeout:coreutils
  psql:postgresql-client haproxy:haproxy Xvfb:xvfb xvfb-run:xvfb xauth:xauth
  docker-compose:docker-compose openssl:openssl python3:python3 clang++:clang
  clang-format:clang-format ccache:ccache cmake:cmake ninja:ninja-build protoc:protobuf-compiler ld.lld:lld
  grpc_cpp_plugin:protobuf-compiler-grpc node:nodejs chromium:chromium
)
[ "$DOCKER" = 1 ] && COMMANDS+=(dockerd:docker.io debootstrap:debootstrap)
if [ "$PEERS" = 1 ]; then
  # DART for bench/contact_peers: its CMake package (find_package(DART CONFIG) in
  # bench/CMakeLists.txt), headers and libraries.
  PACKAGES+=(libdart-dev)
fi

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -gt 0 ]; then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  echo "setup: installing ${#missing[@]} missing packages: ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  echo "setup: done"
fi

# PostgreSQL's server programs (initdb, pg_ctl) live outside PATH, in its versioned folder.
pg_bin=$(ls -d /usr/lib/postgresql/*/bin 2>/dev/null | sort -V | tail -n 1)
absent=()
for entry in "${COMMANDS[@]}"; do
  command -v "${entry%%:*}" >/dev/null 2>&1 || absent+=("${entry%%:*} (package ${entry#*:})")
done
for program in initdb pg_ctl; do
  [ -n "$pg_bin" ] && [ -x "$pg_bin/$program" ] || absent+=("$program (package postgresql)")
done
if [ ${#absent[@]} -gt 0 ]; then
  echo "setup: these commands are still missing after the install: ${absent[*]};" \
    "install the packages named (apt-get install ...) and run setup.sh again" >&2
  exit 1
fi

# The JavaScript packages of the page and of the tests, each folder's pinned by its
# package-lock.json, from the npm registry into FOLDER/node_modules; again only when the lock
# file changed. Debian's npm when node came without it (NodeSource's has one).
npm_folder() {  # npm_folder FOLDER (below the checkout) WHAT-FOR
  local dir
  dir="$(dirname "${BASH_SOURCE[0]}")/../$1"
  if [ -f "$dir/node_modules/.mbstream-installed" ] &&
     [ ! "$dir/package-lock.json" -nt "$dir/node_modules/.mbstream-installed" ]; then
    return 0
  fi
  if ! command -v npm >/dev/null 2>&1; then
    SUDO=""
    if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends npm >/dev/null
  fi
  echo "setup: npm ci in $1 ($2)"
  (cd "$dir" && npm ci --no-audit --no-fund --loglevel=error) >/dev/null
  touch "$dir/node_modules/.mbstream-installed"
}
npm_folder viewer/web "three.js for the web page, playwright-core for its test"
# The MCAP export's independent reader: @mcap/core, Foxglove's ROS 2 message decoder, zstd and
# lz4 decompressors.
npm_folder tests/server/mcap/reader "@mcap/core for the MCAP export's tests"
# A controller in another language for the Control stream's test: @grpc/grpc-js and
# @grpc/proto-loader.
npm_folder tests/server/service/node_control "@grpc/grpc-js for the Node controller test"

# SUNDIALS 6.4.1 with optimisation, from Debian's source package, into a per-user cache that
# CMake prefers (about a minute on 2 cores the first time; instant once cached). Debian's
# libsundials-dev above stays the fallback when the source can't be fetched or built.
if ! bash "$(dirname "${BASH_SOURCE[0]}")/build_sundials.sh"; then
  echo "setup: WARNING: the optimised SUNDIALS could not be built; CMake falls back to Debian's" \
    "libsundials-dev, built WITHOUT optimisation (integration several times slower)." >&2
fi
