#!/usr/bin/env bash
# Installs the Debian 12 packages odomcal needs. Idempotent: packages that are
# already installed are skipped, and `apt-get update` runs at most once.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config
  colmap
  libceres-dev libeigen3-dev libopencv-dev libsqlite3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev nlohmann-json3-dev
  python3-dev python3-numpy pybind11-dev  # the Python module (docs/python.md)
  clang libclang-rt-14-dev  # scripts/sanitize.sh: ASan, UBSan, libFuzzer
  clang-format clang-tidy git  # scripts/check_format.sh, scripts/tidy.sh
  liburdfdom-tools  # check_urdf: the URDF fragment test (robot_description_test)
  libbz2-dev liblz4-dev libzstd-dev python3-rosbag python3-sensor-msgs python3-nav-msgs  # bags: codecs; ROS 1 fixture writer
)

missing=()
for pkg in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$pkg")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

echo "install_deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install_deps: done"
