#!/usr/bin/env bash
# The main job on the embedded default: installs the Debian packages, builds,
# and runs `odomcal demo` (renders the `default` scene -> `odomcal run`:
# COLMAP, then the calibration -> comparison with the ground truth). Extra
# arguments go to `odomcal demo` (`--simulated`: the trajectory-only variant).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
./scripts/build.sh -DODOMCAL_BUILD_TESTS=OFF -DODOMCAL_BUILD_BENCHMARKS=OFF
exec "${ODOMCAL_BUILD_DIR:-build}/plugin/odomcal" demo "$@"
