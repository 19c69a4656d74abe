#!/usr/bin/env bash
# Builds mbstream and runs every test: the one command for a fresh Debian machine.
#   scripts/test.sh            install what is missing, configure, build, run ctest (Release)
#   scripts/test.sh --ci       the same, then the TSan, ASan+UBSan, fuzz and docker stages (CI
#                              runs this):
#     --asan    AddressSanitizer + UndefinedBehaviorSanitizer build (clang, build-asan), the
#               whole suite
#     --tsan    ThreadSanitizer build (clang, build-tsan) of the service, runs and cluster
#               tests
#     --fuzz    the libFuzzer targets, FUZZ_SECONDS each (with --asan: in build-asan, each a
#               ctest test fuzz.TARGET; alone: fuzz/run.sh in build-fuzz)
#     --docker  the tests of label docker (the compose demo and the cluster in Docker, built
#               from the Release tree's programs; Debian's docker.io and debootstrap installed
#               and a daemon started as needed): never in the Release stage's ctest
#   Each stage flag alone adds that stage; --no-release skips the Release stage.
# Environment: BUILD_DIR (default build), JOBS (default 2), CTEST_ARGS (extra ctest flags),
# FUZZ_SECONDS (default 60), CI_BESIDE (with --ci 1: the sanitizer builds and the docker
# images are made in the background while the Release ctest runs; 0: one stage after the
# other), CI_BUDGET_S (with --ci 2700: the stage table says when the run took longer; no stage
# is ever skipped). Suppressions and sanitizer options:
# cmake/sanitizers/ (each entry says why); docs/reliability.md describes the stages and their
# cost.
set -euo pipefail
cd "$(dirname "$0")/.."

RELEASE=1 ASAN=0 TSAN=0 FUZZ=0 DOCKER=0 CI_BESIDE=${CI_BESIDE:-}
while [ $# -gt 0 ]; do
  case "$1" in
    # --ci: every stage (docs/reliability.md, "CI stages"), 30 s per fuzz target.
    # MBSTREAM_CI: a cross-check whose peer library is missing fails instead of skipping
    # (tests/server/loops/simbody_missing.cmake).
    --ci) TSAN=1 ASAN=1 FUZZ=1 DOCKER=1 CI_BESIDE=${CI_BESIDE:-1} CI_BUDGET_S=${CI_BUDGET_S:-2700} FUZZ_SECONDS=${FUZZ_SECONDS:-30}
      export MBSTREAM_CI=1 ;;
    --asan) ASAN=1 ;;
    --tsan) TSAN=1 ;;
    --fuzz) FUZZ=1 ;;
    --docker) DOCKER=1 ;;
    --no-release) RELEASE=0 ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    *) echo "test.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
  shift
done

bash scripts/setup.sh

BUILD_DIR=${BUILD_DIR:-build}
# The compiler cache and the Release configuration, shared with scripts/demo.sh.
source scripts/build_env.sh
ROOT=$PWD
SAN=$ROOT/cmake/sanitizers

TIMES=()
# --ci: every stage runs, always; CI_BUDGET_S (default 2700 = 45 min) is the target the
# whole run is measured against: the stage table says when a run went over it.
BUDGET=${CI_BUDGET_S:-0}
cpu_seconds() {  # user + system CPU seconds of this script's finished children so far
  local ticks
  ticks=$(getconf CLK_TCK)
  awk -v hz="$ticks" '{ sub(/^.*\) /, ""); printf "%d", ($14 + $15) / hz }' "/proc/$$/stat"
}
stage() {  # stage NAME COMMAND...: runs the command, records its wall and CPU time
  local name=$1 start=$SECONDS cpu
  shift
  echo "==== test.sh: $name"
  cpu=$(cpu_seconds)
  "$@"
  TIMES+=("$(printf '%-28s %6d s wall %7d s CPU' "$name" $((SECONDS - start)) \
    $(($(cpu_seconds) - cpu)))")
}
# The budget is the whole run's, the docker stage included (the 45 minutes of .ci/run); the
# docker stage's own time is still printed apart.
DOCKER_S=0
report_times() {
  echo "==== test.sh: stage times (total $SECONDS s wall; the docker stage $DOCKER_S s of it)"
  printf '  %s\n' "${TIMES[@]}"
  if [ "$BUDGET" -gt 0 ] && [ "$SECONDS" -gt "$BUDGET" ]; then
    echo "==== test.sh: OVER BUDGET: $SECONDS s against CI_BUDGET_S=$BUDGET (docs/reliability.md)"
  fi
}
kill_tree() {  # kill_tree PID: the process and every descendant
  local child
  for child in $(pgrep -P "$1" 2>/dev/null); do kill_tree "$child"; done
  kill "$1" 2>/dev/null || true
}
on_exit() {  # background jobs still running (a stage failed first) go with the script
  local pid
  for pid in "${BG_PID[@]}"; do kill -0 "$pid" 2>/dev/null && kill_tree "$pid"; done
  report_times
}
declare -A BG_PID=()
trap on_exit EXIT

configure() { mbstream_configure "$@"; }  # configure DIR extra-cmake-args...
build() { mbstream_build "$@"; }  # build DIR [targets...]
# The last lines of each failed test's output, printed again after ctest's summary: with
# two tests at a time a failure's output lies hundreds of lines up, among passing tests.
failed_outputs() {  # failed_outputs DIR
  local failed=$1/Testing/Temporary/LastTestsFailed.log name
  [ -f "$failed" ] || return 0
  while IFS= read -r name; do
    name=${name#*:}
    echo "==== test.sh: failed: $name (its last 60 lines of output)"
    awk -v name="$name" '
      $0 ~ "^[0-9]+/[0-9]+ Test: " && substr($0, index($0, "Test: ") + 6) == name { inside = 1; next }
      inside && /^<end of output>$/ { exit }
      inside { print }' "$1/Testing/Temporary/LastTest.log" | tail -n 60
  done <"$failed"
}
# Tests run from the checkout's root but never write into it: a run that leaves untracked or
# modified files there fails (scripts/check_clean_tree.sh names them).
run_ctest() {  # run_ctest DIR extra-ctest-args...
  local dir=$1 status=0
  shift
  bash scripts/check_clean_tree.sh snapshot "$dir/source-tree-before-ctest.txt"
  # shellcheck disable=SC2086  # CTEST_ARGS is a list of flags
  (cd "$dir" && ctest --output-on-failure --parallel "$JOBS" "$@" ${CTEST_ARGS:-}) || status=$?
  if [ "$status" != 0 ]; then failed_outputs "$dir"; fi
  bash scripts/check_clean_tree.sh compare "$dir/source-tree-before-ctest.txt" || status=1
  return "$status"
}

if [ "$RELEASE" = 1 ]; then
  stage "release: configure+build" eval 'configure "$BUILD_DIR" && build "$BUILD_DIR"'
fi

# Work beside the foreground stages (--ci, after the Release build): the sanitizer trees'
# builds and the docker stage's images, which wait for no test, run while the Release ctest
# runs, at the lowest CPU and IO priority (nice 19, ionice best-effort 7), so that the tests,
# which leave most of the two cores idle while they wait on their servers, keep the CPU
# whenever they want it. Each job's output goes to build-ci-background/NAME.log, printed when it fails;
# the stage table gives its own wall time and the time the foreground waited for it.
BG_DIR=$ROOT/build-ci-background
background() {  # background NAME COMMAND...: starts COMMAND in the background
  local name=$1
  shift
  mkdir -p "$BG_DIR"
  (
    renice -n 19 -p "$BASHPID" >/dev/null 2>&1 || true
    ionice -c 2 -n 7 -p "$BASHPID" >/dev/null 2>&1 || true
    t0=$(date +%s) status=0
    "$@" >"$BG_DIR/$name.log" 2>&1 || status=$?
    echo "$status $(($(date +%s) - t0))" >"$BG_DIR/$name.done"
    exit "$status"
  ) &
  BG_PID[$name]=$!
}
await() {  # await NAME: waits for the background job NAME; its status
  local name=$1 status=0 start=$SECONDS wall=0
  echo "==== test.sh: waiting for $name (background; log $BG_DIR/$name.log)"
  wait "${BG_PID[$name]}" || status=$?
  [ -f "$BG_DIR/$name.done" ] && read -r _ wall <"$BG_DIR/$name.done"
  TIMES+=("$(printf '%-28s %6d s wall in the background, waited %d s, exit %d' "$name" \
    "$wall" $((SECONDS - start)) "$status")")
  if [ "$status" != 0 ]; then
    echo "==== test.sh: $name exited $status; the last 80 lines of its log:"
    tail -n 80 "$BG_DIR/$name.log"
  fi
  return "$status"
}

# Sanitizer runtime options, inherited by every process a test starts (servers, viewers,
# the CLI). abort_on_error/halt_on_error: a finding fails the test that caused it.
# log_path: every report also goes to a file, because the tests do not look at the exit
# status of the servers and viewers they stop; a stage fails when any report was written.
SAN_LOGS=$ROOT/build-sanitizer-reports
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:strict_string_checks=1:check_initialization_order=1:detect_odr_violation=1:log_path=$SAN_LOGS/asan"
export LSAN_OPTIONS="suppressions=$SAN/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$SAN/ubsan.supp:log_path=$SAN_LOGS/ubsan"
# ignore_noninstrumented_modules: Debian's gRPC/abseil are not built with TSan (why: tsan.supp).
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:ignore_noninstrumented_modules=1:suppressions=$SAN/tsan.supp:log_path=$SAN_LOGS/tsan"

sanitized_ctest() {  # sanitized_ctest DIR ctest-args...: ctest, then no report may exist
  rm -rf "$SAN_LOGS"
  mkdir -p "$SAN_LOGS"
  local status=0
  run_ctest "$@" || status=$?
  if compgen -G "$SAN_LOGS/*" >/dev/null; then
    echo "test.sh: sanitizer reports in $SAN_LOGS:"
    for f in "$SAN_LOGS"/*; do
      echo "---- $f (each stack's first 6 frames; the whole report in the file)"
      # A TSan report's stacks run to 60 frames: kept whole, the report's other stacks and
      # its SUMMARY fell out of CI's excerpt (stop 51's race showed frames #3-#10 only).
      awk '/^ *#[0-9]+ / { if (++frames > 6) next; print; next } { frames = 0; print }' "$f" |
        head -n 120
    done
    status=1
  fi
  return "$status"
}

# The sanitizer builds use clang: libFuzzer needs it, so one build directory serves both
# the ASan + UBSan suite and the fuzz targets (compiled once), and a second compiler's
# code generation is checked besides the Release build's GCC. Warnings are the Release
# build's job (-Werror there), so a clang-only warning does not stop the sanitizer stages.
CLANG=(-DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DMBSTREAM_WERROR=OFF)

# ThreadSanitizer: the tests whose code is threaded: the service (gRPC handlers, run
# manager, fan-out), the run manager, and the cluster (two server processes on a test
# PostgreSQL: proxies, follow relays, leases), and the Control stream (its callback-API reactor:
# the gRPC threads and the run's worker share each call).
TSAN_EXES=(service_test runs_test cluster_e2e_test control_service_test)
tsan_build() {
  configure build-tsan "${CLANG[@]}" -DMBSTREAM_SANITIZE=thread -DMBSTREAM_BUILD_BENCH=OFF
  local available targets=()
  # `help` lists targets as "... NAME" (Makefiles) or "NAME: phony" (Ninja); a list read
  # wrongly was empty, and the stage then built the whole TSan tree (fixed 2026-12-02).
  available=$(cmake --build build-tsan --target help |
    sed -n -e 's/^\.\.\. \([^ ]*\).*/\1/p' -e 's/^\([A-Za-z0-9_.+-]*\): .*/\1/p')
  for t in "${TSAN_EXES[@]}"; do
    if grep -qx "$t" <<<"$available"; then targets+=("$t"); fi
  done
  if [ ${#targets[@]} -eq 0 ]; then
    echo "test.sh: none of ${TSAN_EXES[*]} is a target of build-tsan" >&2
    return 1
  fi
  build build-tsan "${targets[@]}"
}
tsan_ctest() {
  # Only the suites of the executables built (the others are listed as *_NOT_BUILT).
  local suites=() exe name
  for name in "${TSAN_EXES[@]}"; do
    exe=$(find build-tsan/tests -type f -name "$name" -perm -u+x | head -1)
    if [ -n "$exe" ]; then
      mapfile -t -O "${#suites[@]}" suites < <("$exe" --gtest_list_tests |
        sed -n 's/^\([A-Za-z0-9_/]*\)\.$/\1/p')
    fi
  done
  sanitized_ctest build-tsan -R "^($(IFS='|'; echo "${suites[*]}"))\\."
}
ASAN_DIR=${ASAN_BUILD_DIR:-build-asan}
asan_build() {
  # No benchmarks: they are not tests, and they are a fifth of the build.
  # No viewer either (ASAN_VIEWER=1 adds it): its VTK units and Xvfb suites do not fit the
  # CI budget beside the other stages; its translator is fuzzed by hand (fuzz/README.md).
  configure "$ASAN_DIR" "${CLANG[@]}" \
    -DMBSTREAM_SANITIZE=address,undefined -DMBSTREAM_BUILD_FUZZERS=ON \
    -DMBSTREAM_BUILD_BENCH=OFF -DMBSTREAM_BUILD_VIEWER=$([ "${ASAN_VIEWER:-0}" = 1 ] && echo ON || echo OFF) &&
    build "$ASAN_DIR"
}
sanitizer_builds() {  # the TSan tree's programs, then the ASan + UBSan tree
  if [ "$TSAN" = 1 ]; then tsan_build || return 1; fi
  if [ "$ASAN" = 1 ]; then asan_build || return 1; fi
}
# The docker stage's images (the tests' own `docker build`s then find every layer cached):
# the docker packages, the daemon, the base image, the compose demo's and the cluster's images.
docker_images() {
  bash scripts/setup.sh --docker &&
    bash deploy/docker-test.sh --images-only "$BUILD_DIR" &&
    bash deploy/cluster/docker-test.sh --images-only "$BUILD_DIR"
}
BESIDE=0
if [ "$RELEASE" = 1 ] && [ "${CI_BESIDE:-0}" = 1 ]; then
  if [ "$TSAN" = 1 ] || [ "$ASAN" = 1 ]; then
    BESIDE=1
    background "sanitizer builds" sanitizer_builds
  fi
  # A daemon started here is stopped after the docker stage (docker_stage).
  if [ "$DOCKER" = 1 ]; then
    rm -f /tmp/mbstream-dockerd.log.pid
    background "docker images" docker_images
  fi
fi

if [ "$RELEASE" = 1 ]; then
  # The docker label has a stage of its own (below).
  stage "release: ctest" run_ctest "$BUILD_DIR" -LE '^docker$'
fi
if [ "$BESIDE" = 1 ]; then await "sanitizer builds"; fi

if [ "$TSAN" = 1 ]; then
  [ "$BESIDE" = 1 ] || stage "tsan: configure+build" tsan_build
  stage "tsan: ctest" tsan_ctest
fi

if [ "$ASAN" = 1 ]; then
  [ "$BESIDE" = 1 ] || stage "asan+ubsan: configure+build" asan_build
  # Long numerical studies that add nothing under the sanitizers: cmake/sanitizers/asan_skip.txt.
  ASAN_SKIP=$(sed -e 's/#.*//' -e 's/[[:space:]]//g' -e '/^$/d' "$SAN/asan_skip.txt" | paste -sd'|')
  stage "asan+ubsan: ctest" sanitized_ctest "$ASAN_DIR" -LE '^fuzz$' -E "^(${ASAN_SKIP})\$"
fi

# The libFuzzer targets, FUZZ_SECONDS each. In the ASan tree they are built already and each is
# a ctest test (fuzz.TARGET, label fuzz: fuzz/CMakeLists.txt), two at a time; alone (--fuzz
# without --asan), fuzz/run.sh builds them in build-fuzz/ and runs them one after the other.
export FUZZ_SECONDS=${FUZZ_SECONDS:-60}
if [ "$FUZZ" = 1 ]; then
  if [ "$ASAN" = 1 ] && [ -f "$ASAN_DIR/CMakeCache.txt" ]; then
    stage "fuzz: ctest" run_ctest "$ASAN_DIR" -L '^fuzz$'
  else
    stage "fuzz: build+run" bash fuzz/run.sh
  fi
fi

# Docker: the compose demo (deploy/docker-test.sh) and the cluster (deploy/cluster/docker-test.sh)
# brought up for real from the Release tree's programs, on a debootstrapped base image (made
# once, then cached by the daemon). A stage of its own: it needs root, Debian's docker.io and
# debootstrap (setup.sh --docker) and the network for the images' Debian packages.
# A daemon the stage started (deploy/cluster/start-dockerd.sh) is stopped after it.
docker_stage() {
  local status=0 pid
  bash scripts/setup.sh --docker
  [ -n "${BG_PID[docker images]:-}" ] || rm -f /tmp/mbstream-dockerd.log.pid
  run_ctest "$BUILD_DIR" -L '^docker$' || status=$?
  if [ -f /tmp/mbstream-dockerd.log.pid ]; then
    pid=$(cat /tmp/mbstream-dockerd.log.pid)
    kill "$pid" 2>/dev/null && while kill -0 "$pid" 2>/dev/null; do sleep 0.2; done
    rm -f /tmp/mbstream-dockerd.log.pid
  fi
  return "$status"
}
if [ "$DOCKER" = 1 ]; then
  docker_start=$SECONDS
  # Images built beside the other stages; when that failed, the tests build them (and say why).
  if [ -n "${BG_PID[docker images]:-}" ]; then await "docker images" || true; fi
  stage "docker: setup+ctest" docker_stage
  DOCKER_S=$((SECONDS - docker_start))
fi
