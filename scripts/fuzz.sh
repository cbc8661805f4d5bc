#!/usr/bin/env bash
# Long fuzzing run of one target: scripts/fuzz.sh TARGET SECONDS [libFuzzer flags]
#   TARGET   a tests/fuzz/<TARGET>_fuzzer.cc, e.g. colmap_binary_model
#   SECONDS  wall-clock time (libFuzzer -max_total_time)
# Builds <TARGET>_fuzzer in the sanitizer build directory of scripts/sanitize.sh
# (ASan + UBSan + libFuzzer), then fuzzes under `nice -n 10` with one job.
# The working corpus ${ODOMCAL_FUZZ_WORK:-build-sanitize/fuzz-long}/TARGET/corpus
# starts as a copy of tests/fuzz/corpus/TARGET and grows across runs; crash,
# timeout and out-of-memory inputs go to .../TARGET/artifacts/. The checked-in
# corpus is never written: see docs/fuzzing.md for adding inputs to it.
# Prints CPU time, executions per second, corpus size and the findings.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 2 ]; then
  echo "usage: $0 TARGET SECONDS [libFuzzer flags]; targets:" \
       "$(cd tests/fuzz && ls -- *_fuzzer.cc | sed 's/_fuzzer.cc//' | tr '\n' ' ')" >&2
  exit 2
fi
target="$1"
seconds="$2"
shift 2
if [ ! -f "tests/fuzz/${target}_fuzzer.cc" ]; then
  echo "fuzz: no tests/fuzz/${target}_fuzzer.cc" >&2
  exit 2
fi
build_dir="${ODOMCAL_SANITIZE_BUILD_DIR:-build-sanitize}"
work="${ODOMCAL_FUZZ_WORK:-$build_dir/fuzz-long}/$target"

export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}"
if [ -z "${TMPDIR:-}" ] && [ -w /dev/shm ]; then export TMPDIR=/dev/shm; fi

# ODOMCAL_FUZZ_SKIP_BUILD=1 fuzzes the binary as built, e.g. while the
# source tree is being edited.
if [ "${ODOMCAL_FUZZ_SKIP_BUILD:-0}" != 1 ]; then
  ODOMCAL_SANITIZE_BUILD_DIR="$build_dir" ./scripts/sanitize.sh --configure-only
  nice -n 10 cmake --build "$build_dir" -j "${ODOMCAL_JOBS:-2}" \
    --target "${target}_fuzzer" >/dev/null
fi

mkdir -p "$work/corpus" "$work/artifacts"
cp -n tests/fuzz/corpus/"$target"/* "$work/corpus/"
echo "fuzz: $target for ${seconds}s, log in $work/log.txt"
TIMEFORMAT="fuzz: $target wall %R s, CPU %U s user + %S s system"
status=0
time nice -n 10 "$build_dir/tests/fuzz/${target}_fuzzer" \
  -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
  -dict="tests/fuzz/$target.dict" -artifact_prefix="$work/artifacts/" \
  -print_final_stats=1 "$@" "$work/corpus" >"$work/log.txt" 2>&1 || status=$?

grep -E "^stat::(number_of_executed_units|average_exec_per_sec|new_units_added|peak_rss_mb)" \
  "$work/log.txt" || true
echo "fuzz: corpus $(find "$work/corpus" -type f | wc -l) files," \
     "$(du -sk "$work/corpus" | cut -f1) KiB"
findings=$(find "$work/artifacts" -type f | wc -l)
echo "fuzz: $findings finding(s) in $work/artifacts"
if [ "$status" -ne 0 ]; then
  tail -n 60 "$work/log.txt" >&2
  echo "fuzz: $target exited with status $status" >&2
fi
exit "$status"
