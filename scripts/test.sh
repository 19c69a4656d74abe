#!/usr/bin/env bash
# Builds mbstream and runs every test: the one command for a fresh Debian machine.
#   scripts/test.sh            install what is missing, configure, build, run ctest
# Environment: BUILD_DIR (default build), JOBS (default 2), CTEST_ARGS (extra ctest flags).
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup.sh

BUILD_DIR=${BUILD_DIR:-build}
JOBS=${JOBS:-2}
export CCACHE_DIR=${CCACHE_DIR:-$HOME/.cache/ccache}
export CCACHE_MAXSIZE=${CCACHE_MAXSIZE:-2G}
# Paths under the checkout are hashed relative to it: a second checkout reuses the cache.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD}

cmake -S . -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DMBSTREAM_WERROR=ON
cmake --build "$BUILD_DIR" --parallel "$JOBS"
cd "$BUILD_DIR"
ctest --output-on-failure --parallel "$JOBS" ${CTEST_ARGS:-}
