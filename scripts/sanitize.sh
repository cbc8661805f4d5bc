#!/usr/bin/env bash
# Clang build with AddressSanitizer + UndefinedBehaviorSanitizer and the
# libFuzzer targets, in ${ODOMCAL_SANITIZE_BUILD_DIR:-build-sanitize}.
#   scripts/sanitize.sh [--scope all|parsers] [--configure-only]
# --scope all (the default; before a release and after changes to solver/):
#   1. `ctest -L unit`: every unit test (but the Monte Carlo statistics) and
#      every fuzz corpus replay under ASan/UBSan, then the CLI tests
#      (cli_test, colmap_cli_test); any report fails the job (UBSan does not
#      recover).
#   2. Each fuzzer for ${ODOMCAL_FUZZ_SECONDS:-15} seconds on a COPY of its
#      checked-in corpus (tests/fuzz/corpus is never written here); a crash
#      fails the job and its input is kept under <build dir>/fuzz/<target>/.
#   Benchmarks, the rendered e2e tests and paper_evaluation_test are not
#   built (see not_sanitized below).
# --scope parsers (CI, .ci/run): the fuzz targets of the file parsers only,
#   their corpus replays and the fuzzing of step 2, with solver/ compiled
#   uninstrumented (ODOMCAL_SANITIZE_SOLVER=OFF): a few minutes instead of
#   the whole instrumented build.
# Long fuzzing runs: scripts/fuzz.sh (see docs/fuzzing.md), which calls
# `sanitize.sh --configure-only` to get the same build directory.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${ODOMCAL_SANITIZE_BUILD_DIR:-build-sanitize}"
jobs="${ODOMCAL_JOBS:-$(nproc)}"
fuzz_seconds="${ODOMCAL_FUZZ_SECONDS:-15}"
scope=all
configure_only=false
while [ $# -gt 0 ]; do
  case "$1" in
    --scope) scope="${2:-}"; shift 2 || { echo "sanitize: --scope needs all or parsers" >&2; exit 2; } ;;
    --scope=*) scope="${1#--scope=}"; shift ;;
    --configure-only) configure_only=true; shift ;;
    *) echo "sanitize: unknown argument '$1' (--scope all|parsers, --configure-only)" >&2; exit 2 ;;
  esac
done
case "$scope" in
  all) sanitize_solver=ON ;;
  parsers) sanitize_solver=OFF ;;
  *) echo "sanitize: --scope must be all or parsers, got '$scope'" >&2; exit 2 ;;
esac
start=$(date +%s)
./scripts/install_deps.sh

# halt_on_error for UBSan too: a report must fail the test that caused it.
export ASAN_OPTIONS="${ASAN_OPTIONS:-abort_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"
# In-memory scratch files for the fuzzers (tests/fuzz/scratch_dir.h).
if [ -z "${TMPDIR:-}" ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi

# -O1 with line tables: the usual sanitizer trade-off of speed and readable
# stack traces; asserts stay on (no NDEBUG).
cmake -S . -B "$build_dir" \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" \
  -DCMAKE_CXX_FLAGS="-fno-sanitize-recover=all" \
  -DODOMCAL_ENABLE_SANITIZERS=ON \
  -DODOMCAL_SANITIZE_SOLVER="$sanitize_solver" \
  -DODOMCAL_BUILD_FUZZERS=ON \
  -DODOMCAL_BUILD_TESTS=ON \
  -DODOMCAL_BUILD_BENCHMARKS=OFF >/dev/null
if [ "$configure_only" = true ]; then exit 0; fi

# Fuzz targets: one per tests/fuzz/<name>_fuzzer.cc.
fuzz_targets=()
for source in tests/fuzz/*_fuzzer.cc; do
  name=$(basename "$source" .cc)
  fuzz_targets+=("${name%_fuzzer}")
done
# The unit test binaries, minus the ones below; every other *_test target
# must be listed in one of the two arrays, so that a new unit test binary is
# not left unbuilt (ctest would skip it without a word).
unit_tests=(solver_test adapters_test bag_ros1_test bag_ros2_test bag_extract_test datasets_test
            output_test colmap_test report_test robustness_test command_line_test)
# e2e-labelled CLI runs of the sanitized odomcal executable (seconds each;
# their ctest label is e2e, so they are selected by test name below).
cli_tests=(cli_test colmap_cli_test rig_cli_test colmap_rig_cli_test)
cli_test_regex='^(OdomcalCli|ColmapCli|RigCli|ColmapRigCli)\.'
# rendered_e2e_test (COLMAP for minutes, in scripts/test.sh) and
# paper_evaluation_test: Monte Carlo reproductions of the paper's tables that
# take 10 minutes under ASan (its solver and dataset code is covered by
# solver_test and datasets_test) and whose 2 % batch tolerance does not hold
# with clang -O1.
not_sanitized=(rendered_e2e_test paper_evaluation_test)
for target in $(cmake --build "$build_dir" --target help | sed -n 's/^\.\.\. \([a-z0-9_]*_test\)$/\1/p'); do
  case " ${unit_tests[*]} ${cli_tests[*]} ${not_sanitized[*]} " in
    *" $target "*) ;;
    *) echo "sanitize: $target is in none of unit_tests, cli_tests, not_sanitized in $0" >&2
       exit 1 ;;
  esac
done
build_targets=()
if [ "$scope" = all ]; then build_targets=("${unit_tests[@]}" "${cli_tests[@]}"); fi
for target in "${fuzz_targets[@]}"; do
  build_targets+=("${target}_replay" "${target}_fuzzer")
done
cmake --build "$build_dir" -j "$jobs" --target "${build_targets[@]}"
build_end=$(date +%s)

# Tests of binaries not built above are *_NOT_BUILT, without a label; in a
# reused build folder, forget the tests of any such binary built earlier.
for target in "${not_sanitized[@]}"; do
  find "$build_dir" -name "${target}\[*\]_tests.cmake" -delete
done
# Monte Carlo checks of accuracy and consistency repeat one calibration over
# many seeds or thousands of pairs (minutes each under ASan, about 60x their
# Release time); the sanitizers learn nothing from the repetitions: the
# single-run tests of the same code (CalibrateOdomCam.*, NoiseEstimation.*,
# NoiseRefinement.RemovesOutliersAndKeepsGoodPairs) run here, and these run
# in scripts/test.sh.
statistical_tests='^(CalibrateOdomCam\.NoisyMonteCarloIsAccurateAndConsistent|CalibrateSe3Odometry\.NoisyDrivesAreWithinThreeSigma|NoiseRefinement\.RejectsFewGoodPairsUnderTheEstimatedNoise)$'
if [ "$scope" = all ]; then
  (cd "$build_dir" &&
    ctest -L unit -E "$statistical_tests" --output-on-failure -j "$jobs" &&
    ctest -R "$cli_test_regex" --output-on-failure -j "$jobs")
else
  (cd "$build_dir" && ctest -R '^Fuzz\.' --output-on-failure -j "$jobs")
fi
test_end=$(date +%s)

fuzz_root="$build_dir/fuzz"
for target in "${fuzz_targets[@]}"; do
  work="$fuzz_root/$target"
  rm -rf "$work"
  mkdir -p "$work/corpus" "$work/artifacts"
  cp tests/fuzz/corpus/"$target"/* "$work/corpus/"
  echo "sanitize: fuzzing $target for ${fuzz_seconds}s"
  if ! "$build_dir/tests/fuzz/${target}_fuzzer" \
      -max_total_time="$fuzz_seconds" -timeout=10 -rss_limit_mb=2048 \
      -dict=tests/fuzz/"$target".dict -artifact_prefix="$work/artifacts/" \
      -print_final_stats=1 "$work/corpus" >"$work/log.txt" 2>&1; then
    tail -n 60 "$work/log.txt" >&2
    echo "sanitize: $target found a crash; inputs in $work/artifacts" >&2
    exit 1
  fi
  grep -E "^stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)" "$work/log.txt" | sed "s/^/  /"
done
end=$(date +%s)
echo "sanitize ($scope): build $((build_end - start))s, tests $((test_end - build_end))s," \
     "fuzzing $((end - test_end))s, total $((end - start))s"
