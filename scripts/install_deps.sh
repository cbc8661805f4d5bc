#!/usr/bin/env bash
# Installs the Debian 12 packages odomcal needs, then the npm packages that
# write the ROS 2 bag test fixtures. Idempotent: packages that are already
# installed are skipped, `apt-get update` runs at most once, and `npm ci`
# runs only when tests/fixtures/bags/package-lock.json changed.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  colmap
  libceres-dev libeigen3-dev libopencv-dev libsqlite3-dev
  libsuitesparse-dev  # AMD: the joint adjustment covariance's fill-reducing order
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev nlohmann-json3-dev
  python3-dev python3-numpy pybind11-dev  # the Python module (docs/python.md)
  clang libclang-rt-14-dev  # scripts/sanitize.sh: ASan, UBSan, libFuzzer
  clang-format clang-tidy git  # scripts/check_format.sh, scripts/tidy.sh
  liburdfdom-tools  # check_urdf: the URDF fragment test (robot_description_test)
  libbz2-dev liblz4-dev libzstd-dev zlib1g-dev libyaml-cpp-dev  # adapters/bag: bag codecs, metadata.yaml
  python3-rosbag python3-sensor-msgs python3-nav-msgs nodejs  # test fixtures: ROS 1 by rosbag, ROS 2 by node
)

missing=()
for pkg in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$pkg")
  fi
done
# npm comes with some builds of nodejs; Debian's own is a separate package.
if ! command -v npm >/dev/null; then missing+=(npm); fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
else
  echo "install_deps: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  echo "install_deps: done"
fi

# The npm packages that write the ROS 2 bag fixtures (tests/fixtures/bags),
# installed again whenever the lock file differs from the one installed.
fixtures="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/tests/fixtures/bags"
installed_lock="$fixtures/node_modules/.odomcal-package-lock.json"
if ! cmp -s "$fixtures/package-lock.json" "$installed_lock"; then
  echo "install_deps: npm ci in tests/fixtures/bags"
  npm ci --prefix "$fixtures" --no-audit --no-fund --silent >/dev/null
  cp "$fixtures/package-lock.json" "$installed_lock"
fi
