#!/usr/bin/env bash
# Writes report.html from a real calibration of a simulated COLMAP project
# (the ColmapReport unit tests' run: a folded stretch, plus made-up mapper
# attempts and a long warning with markup to show the table and wrapping) and
# screenshots it with headless Chromium.
#   scripts/report_screenshot.sh [BUILD_DIR] [OUTPUT_PNG]
# BUILD_DIR defaults to ./build (configured with -DODOMCAL_BUILD_TESTS=ON).
set -euo pipefail
build_dir=$(realpath "${1:-build}")
output_png=$(realpath -m "${2:-report.png}")
mkdir -p "$(dirname "$output_png")"
work_dir=$(mktemp -d)
trap 'rm -rf "$work_dir"' EXIT

cmake --build "$build_dir" --target report_test >/dev/null
TEST_TMPDIR="$work_dir" ODOMCAL_KEEP_TEST_FILES=1 \
  "$build_dir/plugin/report/report_test" --gtest_filter='ColmapReport.*' >/dev/null
report=$(echo "$work_dir"/colmap_report_test_*/out/report.html)
cp "$report" "${output_png%.png}.html"
chromium --headless --no-sandbox --disable-gpu --disable-quic --no-first-run \
  --disable-background-networking --disable-component-update --disable-sync \
  --user-data-dir="$work_dir/chromium" --window-size=1280,3000 \
  --screenshot="$output_png" "file://$report" 2>/dev/null
echo "wrote $output_png and ${output_png%.png}.html"
