#!/usr/bin/env bash
# Installs the Debian packages, builds everything (tests and benchmarks) and
# runs every test: unit tests and end-to-end tests (ctest labels unit, e2e).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh -DODOMCAL_BUILD_TESTS=ON -DODOMCAL_BUILD_BENCHMARKS=ON
cd "${ODOMCAL_BUILD_DIR:-build}"
ctest --output-on-failure -j "${ODOMCAL_JOBS:-$(nproc)}"
