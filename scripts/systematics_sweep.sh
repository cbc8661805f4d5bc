#!/bin/bash
# Measures the clock-offset and odometry-intrinsics estimation on simulated
# 2-minute drives (50 Hz odometry, 5 Hz camera; manoeuvres and smooth
# driving): prints, per seed and case,
# the demo's errors against the ground truth (docs/systematics.md).
# Usage: scripts/systematics_sweep.sh <odomcal binary> <work folder> [seeds]
set -euo pipefail
odomcal=$1
work=$2
seeds=${3:-"1 2 3 4 5"}
mkdir -p "$work"
run() {  # name, flags...
  local name=$1
  shift
  for seed in $seeds; do
    "$odomcal" demo --simulated --workspace_path "$work/$name-$seed" \
      --seed "$seed" --sim_camera_rate_hz 5 "$@" >"$work/$name-$seed.txt" || true
    awk -v n="$name" -v s="$seed" '
      /rotation error/ {r=$3} /translation error/ {x=$4; y=$7}
      /time offset error/ {o=$4} /yaw_scale error/ {ys=$3}
      /yaw_per_metre error/ {ypm=$3}
      END {printf "%-12s seed %s rot %s deg x %s mm y %s mm offset %s ms yaw_scale %s %% ypm %s rad/m\n", n, s, r, x, y, o, ys, ypm}' \
      "$work/$name-$seed.txt"
  done
}
exact="--sim_wheel_radius_left 1 --sim_wheel_radius_right 1 --sim_yaw_rate_bias_radps 0"
off="--estimate_time_offset off --estimate_odometry_intrinsics off"
wheels="--sim_wheel_radius_left 1.015 --sim_wheel_radius_right 0.99 --sim_wheel_track 0.03"
# Baseline: exact odometry, no offset, nothing estimated (odomcal before).
run base $exact $off
for offset in -0.3 0.05 0.3; do
  run "offset$offset" $exact --sim_camera_time_offset_s "$offset"
done
run offset0.3_off $exact --sim_camera_time_offset_s 0.3 $off
run wheels $wheels --sim_yaw_rate_bias_radps 0
run wheels_off $wheels --sim_yaw_rate_bias_radps 0 $off
run wheels_bias $wheels --sim_yaw_rate_bias_radps 0.002
run wheels_track $wheels --sim_yaw_rate_bias_radps 0 --wheel_track_m 0.4
# Smooth driving (--sim_profile smooth: speed and yaw rate slow sinusoids),
# whose coarse correlation peak is flat: the same offsets, and the same
# drive without an offset as the reference.
smooth="$exact --sim_profile smooth"
run smooth_base $smooth
for offset in -0.3 0.05 0.3; do
  run "smooth_offset$offset" $smooth --sim_camera_time_offset_s "$offset"
done
