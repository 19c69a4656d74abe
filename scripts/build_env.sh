# Sourced by scripts/demo.sh and scripts/test.sh: the one configuration of the Release tree
# and its compiler cache, so that the two README commands share build/ and whichever runs
# second compiles nothing the first compiled (same flags, same cache keys).
#   mbstream_configure DIR [cmake-args...]   Release, -Werror, ccache; extra args appended
#   mbstream_build DIR [targets...]          JOBS (default 2) compile jobs
# shellcheck shell=bash

export CCACHE_DIR=${CCACHE_DIR:-$HOME/.cache/ccache}
export CCACHE_MAXSIZE=${CCACHE_MAXSIZE:-5G}
# Paths under the checkout are hashed relative to it: a second checkout reuses the cache.
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD}
# The sanitizer builds have debug line tables (-g1): without this ccache would hash the
# build directory into every such object and a second checkout would miss.
export CCACHE_NOHASHDIR=${CCACHE_NOHASHDIR:-1}
JOBS=${JOBS:-2}

mbstream_configure() {  # mbstream_configure DIR [cmake-args...]
  local dir=$1 generator=()
  shift
  # Ninja for a new tree (it schedules the 2 jobs better than make); an existing tree keeps
  # the generator it was made with (CMake refuses to change it).
  if [ ! -f "$dir/CMakeCache.txt" ] && command -v ninja >/dev/null; then generator=(-G Ninja); fi
  cmake -S . -B "$dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DMBSTREAM_WERROR=ON "$@"
}

mbstream_build() {  # mbstream_build DIR [targets...]
  local dir=$1
  shift
  if [ $# -gt 0 ]; then
    cmake --build "$dir" --parallel "$JOBS" --target "$@"
  else
    cmake --build "$dir" --parallel "$JOBS"
  fi
}
