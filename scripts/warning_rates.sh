#!/bin/bash
# How often the planarity, clock-offset and scale drift warnings fire on simulated
# 2-minute drives (docs/statistics.md, "Warnings"): flat synchronised drives
# with the odometry as CSV (x, y, yaw) and as TUM (the same poses as
# quaternions), manoeuvres and smooth driving, and drives over ground tilted
# +-3 deg, which must be named. Prints per case the runs with each warning
# and the planarity statistics' range.
# Usage: scripts/warning_rates.sh <odomcal binary> <work folder> [seeds]
set -euo pipefail
odomcal=$1
work=$2
seeds=${3:-$(seq 1 30)}
mkdir -p "$work"
tally() {  # case name, then one calibration.json per seed on stdin
  python3 -c '
import json, sys
name = sys.argv[1]
runs = planar = offset = drift = 0
rc, cl = [], []
for path in sys.stdin.read().split():
    r = json.load(open(path))
    runs += 1
    w = " ".join(r.get("warnings", []))
    planar += "not planar" in w
    offset += "camera_time_offset_s not estimated" in w
    drift += "scale wanders" in w
    p = r.get("diagnostics", {}).get("planarity") or {}
    if p.get("checked"):
        rc.append(p["reduced_chi_square"]); cl.append(p["correlation_length"])
fmt = lambda v: "%.2f-%.2f" % (min(v), max(v)) if v else "-"
print("%-22s runs %2d  planarity warnings %2d  offset warnings %2d  scale drift warnings %2d  reduced chi2 %s  correlation %s"
      % (name, runs, planar, offset, drift, fmt(rc), fmt(cl)))' "$1"
}
run_case() {  # name, demo flags...
  local name=$1
  shift
  for seed in $seeds; do
    "$odomcal" demo --simulated --workspace_path "$work/$name-$seed" \
      --seed "$seed" --sim_camera_rate_hz 5 "$@" >/dev/null 2>&1 || true
  done
  for seed in $seeds; do echo "$work/$name-$seed/calibration.json"; done | tally "$name"
}
# The same drive's odometry as TUM poses (planar: z 0, rotation about z).
run_tum() {  # name of a finished CSV case
  local name=$1
  for seed in $seeds; do
    local dir="$work/$name-$seed"
    awk -F, 'NR > 1 {printf "%s %s %s 0 0 0 %.17g %.17g\n", $1, $2, $3, sin($4 / 2), cos($4 / 2)}' \
      "$dir/odometry.csv" >"$dir/odometry.tum"
    "$odomcal" calibrate --camera_poses "$dir/camera.tum" --odometry "$dir/odometry.tum" \
      --output "$dir/tum.json" --overwrite >/dev/null 2>&1 || true
  done
  for seed in $seeds; do echo "$work/$name-$seed/tum.json"; done | tally "$name (TUM)"
}
run_case flat
run_tum flat
run_case flat_smooth --sim_profile smooth
run_tum flat_smooth
run_case tilted_3deg --ground_tilt_deg 3
