#!/usr/bin/env bash
# Configures and builds odomcal (Release) into ${ODOMCAL_BUILD_DIR:-build}.
# Extra arguments are passed to cmake's configure step.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${ODOMCAL_BUILD_DIR:-build}"
jobs="${ODOMCAL_JOBS:-$(nproc)}"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$build_dir" -j "$jobs"
