#!/usr/bin/env bash
# Installs the Debian packages, builds everything (tests and benchmarks) and
# runs every test: unit tests and end-to-end tests (ctest labels unit, e2e).
# ODOMCAL_WARNINGS_AS_ERRORS=ON (CI) compiles odomcal's own code with -Werror.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh -DODOMCAL_BUILD_TESTS=ON -DODOMCAL_BUILD_BENCHMARKS=ON \
  -DODOMCAL_WARNINGS_AS_ERRORS="${ODOMCAL_WARNINGS_AS_ERRORS:-OFF}"
cd "${ODOMCAL_BUILD_DIR:-build}"
ctest --output-on-failure -j "${ODOMCAL_JOBS:-$(nproc)}"
