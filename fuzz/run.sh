#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) and runs each for a bounded time.
#   fuzz/run.sh [--seconds N] [--no-build] [--replay] [TARGET...]    default: 60 s each, every target
# --replay: the targets are the seed replayers of a tree without libFuzzer (the Release tree:
# fuzz/seed_replay_main.cc); each is given every seed once, no fuzzing.
# Environment: FUZZ_SECONDS (the default of --seconds), FUZZ_BUILD_DIR (default build-fuzz;
# CI: build-asan, where each target is also a ctest test, fuzz.TARGET), JOBS (default 2).
# The corpus each target grows is kept in $FUZZ_BUILD_DIR/fuzz/corpus/TARGET, so a later run
# goes on from it; crashing inputs go to $FUZZ_BUILD_DIR/fuzz/artifacts/. Prints, per target, the time
# run, the executions and executions per second; exits 1 if any target found a crash.
set -euo pipefail
cd "$(dirname "$0")/.."

SECONDS_PER_TARGET=${FUZZ_SECONDS:-60}
TARGETS=()
BUILD_STEP=1
REPLAY=0
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds) SECONDS_PER_TARGET=$2; shift 2 ;;
    --no-build) BUILD_STEP=0; shift ;;
    --replay) REPLAY=1; shift ;;
    -h|--help) sed -n '2,8p' "$0"; exit 0 ;;
    *) TARGETS+=("$1"); shift ;;
  esac
done
ALL_TARGETS=(urdf_import_fuzzer sdf_import_fuzzer scene_script_fuzzer run_spec_json_fuzzer
             start_run_fuzzer)

BUILD=${FUZZ_BUILD_DIR:-build-fuzz}
JOBS=${JOBS:-2}
export CCACHE_DIR=${CCACHE_DIR:-$HOME/.cache/ccache}
export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD}

# A build directory already configured with MBSTREAM_BUILD_FUZZERS=ON (scripts/test.sh
# --asan configures build-asan so, tests included) is used as it is. Otherwise one is
# configured with tests and benchmarks off, and only the libraries the targets link are
# built: the viewer's VTK parts are configured but never compiled here.
if [ "$BUILD_STEP" = 0 ]; then
  :
elif ! grep -qs '^MBSTREAM_BUILD_FUZZERS:BOOL=ON' "$BUILD/CMakeCache.txt"; then
  cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_COMPILER=clang \
    -DCMAKE_CXX_COMPILER=clang++ -DMBSTREAM_BUILD_FUZZERS=ON -DMBSTREAM_BUILD_TESTS=OFF \
    -DMBSTREAM_BUILD_BENCH=OFF
fi
# Without targets named, every target the build directory has: scene_script_fuzzer exists
# only where the viewer is built (CI's build-asan leaves the viewer out: docs/reliability.md).
if [ ${#TARGETS[@]} -eq 0 ]; then
  available=$(cmake --build "$BUILD" --target help | sed -n 's/^\.\.\. \([^ ]*\).*/\1/p')
  for t in "${ALL_TARGETS[@]}"; do
    if grep -qx "$t" <<<"$available"; then
      TARGETS+=("$t")
    else
      echo "fuzz/run.sh: $t is not in $BUILD (its component is not built there): skipped"
    fi
  done
fi
if [ "$BUILD_STEP" = 1 ]; then
  cmake --build "$BUILD" --parallel "$JOBS" --target "${TARGETS[@]}"
fi

# Seed corpora: the shipped models and the tests' data, plus fuzz/seeds/ (small, checked in),
# written per target (ctest runs two targets at once, each its own fuzz/run.sh).
OUT=$BUILD/fuzz
SEEDS=$OUT/seeds
mkdir -p "$OUT/artifacts" "$OUT/logs"
write_seeds() {  # write_seeds TARGET: fills $SEEDS/TARGET afresh
  local dir=$SEEDS/$1 n=0 urdf spec specs
  rm -rf "$dir"
  mkdir -p "$dir"
  case "$1" in
    urdf_import_fuzzer) cp models/*/*.urdf fuzz/seeds/urdf/* "$dir/" ;;
    sdf_import_fuzzer) cp models/*/*.sdf tests/data/*.sdf fuzz/seeds/sdf/* "$dir/" ;;
    scene_script_fuzzer) cp models/*/*.scene tests/viewer/data/*.txt fuzz/seeds/scene/* "$dir/" ;;
    run_spec_json_fuzzer) cp models/*/*.json fuzz/seeds/run_spec/* "$dir/" ;;
    start_run_fuzzer)
      # Whole requests: each shipped model with each spec, shortened to fit the fuzzer's
      # limits (start_run_fuzzer.cc: 0.2 s, 200 frames), plus the checked-in ones. Not
      # models/big/: the first step of the 100-link chain with six prescribed joints (its
      # sanity check and a 200-column Jacobian) costs 0.2 s of CPU in a release build and over
      # 20 s under ASan, close to libFuzzer's 30 s timeout; those files seed
      # urdf_import_fuzzer above, and what the fuzzer tests here (a request's validation) they
      # would not exercise any further. The linkages (SDFormat, closed loops) each with their
      # own specs.
      for urdf in models/*/*.urdf models/linkages/*.sdf; do
        case "$urdf" in
          models/big/*) continue ;;
          models/linkages/*) specs=("${urdf%.sdf}"-*.json) ;;
          *) specs=(models/*/*.json fuzz/seeds/run_spec/*) ;;
        esac
        for spec in "${specs[@]}"; do
          n=$((n + 1))
          { cat "$urdf"; printf '\n@@spec\n'
            sed -E 's/"duration_s": *[0-9.eE+-]+/"duration_s": 0.1/' "$spec"; } \
            >"$dir/model-spec-$n"
        done
      done
      cp fuzz/seeds/start_run/* "$dir/"
      ;;
  esac
}

# The fuzzer reports on its own output (scripts/test.sh's options send reports to files).
export ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/cmake/sanitizers/lsan.supp:print_suppressions=0
declare -A DICT=([urdf_import_fuzzer]=urdf [sdf_import_fuzzer]=sdf [scene_script_fuzzer]=scene_script
                 [run_spec_json_fuzzer]=run_spec [start_run_fuzzer]=start_run)
failed=0
if [ "$REPLAY" = 1 ]; then
  for target in "${TARGETS[@]}"; do
    write_seeds "$target"
    log=$OUT/logs/$target.replay.log
    if "$BUILD/fuzz/$target" "$SEEDS/$target"/* >"$log" 2>&1; then
      tail -n 1 "$log"
    else
      failed=1
      echo "fuzz: $target FAILED on a seed (the last seed named below); the end of $log:"
      tail -n 30 "$log"
    fi
  done
  exit "$failed"
fi
header=$(printf '%-22s %8s %12s %10s %8s' target seconds executions exec/s corpus)
echo "$header"
for target in "${TARGETS[@]}"; do
  write_seeds "$target"
  corpus=$OUT/corpus/$target
  mkdir -p "$corpus"
  log=$OUT/logs/$target.log
  status=0
  # -timeout: an input taking 30 s is a finding (a hang); -rss_limit_mb: so is 2 GB of memory.
  "$BUILD/fuzz/$target" "$corpus" "$SEEDS/$target" -max_total_time="$SECONDS_PER_TARGET" \
    -dict="fuzz/dict/${DICT[$target]}.dict" -timeout=30 -rss_limit_mb=2048 \
    -artifact_prefix="$OUT/artifacts/$target-" -print_final_stats=1 >"$log" 2>&1 || status=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  files=$(find "$corpus" -type f | wc -l)
  printf '%-22s %8s %12s %10s %8s\n' "$target" "$SECONDS_PER_TARGET" "${execs:-?}" "${rate:-?}" \
    "$files" | tee "$OUT/logs/$target.summary"
  if [ "$status" -ne 0 ]; then
    failed=1
    echo "fuzz: $target FAILED (exit $status); the end of $log:"
    tail -n 60 "$log"
  fi
done
# Every target's last run, in one table.
{ echo "$header"; cat "$OUT"/logs/*.summary; } >"$OUT/summary.txt"
exit "$failed"
