#!/usr/bin/env bash
# The road drives of issue-sized coverage: per preset (`road`, `road_sloped`)
# and seed, render the drive, run `odomcal run` on it with its planar wheel
# odometry (defaults, true intrinsics), then `odomcal colmap` on the same
# model with the car's SE(3) odometry (`odometry_se3.tum`) and with the
# planar odometry and `--joint_adjustment on` (the default is `check`; not
# with ROAD_STUDY_JOINT_ON=0); with
# ROAD_STUDY_REPEAT=1 a second `odomcal run` into a fresh workspace, to
# compare the two. scripts/road_study_summary.py makes the tables of
# docs/e2e_measurements.md from the results.
#
#   scripts/road_study.sh [PRESETS (default "road road_sloped")] [SEEDS (default "1 2 ... 10")]
#
# Needs build/plugin/odomcal (or $ODOMCAL) and colmap; 3-12 min per drive on
# 2 cores. Writes $ROAD_STUDY_ROOT (default /tmp/odomcal_road_study):
# NAME (the render), NAME_ws (the run, planar odometry), NAME_se3 (SE(3)),
# NAME_on (the joint adjustment on), NAME_repeat (the second run), with NAME = PRESET + SEED; a rerun reuses
# every finished COLMAP stage and calibrates again.
set -euo pipefail
cd "$(dirname "$0")/.."
odomcal=${ODOMCAL:-$PWD/build/plugin/odomcal}
presets=${1:-road road_sloped}
seeds=${2:-1 2 3 4 5 6 7 8 9 10}
root=${ROAD_STUDY_ROOT:-/tmp/odomcal_road_study}
mkdir -p "$root"

timed() {  # stem command...: stem.seconds, stem.exit
  local stem=$1 start code=0
  shift
  start=$(date +%s.%N)
  "$@" || code=$?
  echo "$(date +%s.%N) - $start" | bc > "$stem.seconds"
  echo "$code" > "$stem.exit"
}

for preset in $presets; do
  for seed in $seeds; do
    name=$preset$seed
    data=$root/$name
    if [ ! -f "$data/ground_truth.json" ]; then
      "$odomcal" render --preset "$preset" --seed "$seed" --output_path "$data" \
        --overwrite > "$data.render.log" 2>&1
    fi
    run=(run --image_path "$data/images" --image_timestamps "$data/image_timestamps.csv"
         --camera_model PINHOLE --camera_params 370,370,320,100)
    timed "$data.run" "$odomcal" "${run[@]}" --odometry "$data/odometry.csv" \
      --workspace_path "${data}_ws" > "$data.run.log" 2>&1
    if [ -d "${data}_ws/sparse" ]; then
      timed "$data.se3" "$odomcal" colmap --model_path "${data}_ws/sparse" \
        --database_path "${data}_ws/database.db" --odometry "$data/odometry_se3.tum" \
        --image_timestamps "$data/image_timestamps.csv" --output_path "${data}_se3" \
        --overwrite > "$data.se3.log" 2>&1
    fi
    if [ -d "${data}_ws/sparse" ] && [ "${ROAD_STUDY_JOINT_ON:-1}" = 1 ]; then
      timed "$data.on" "$odomcal" colmap --model_path "${data}_ws/sparse" \
        --database_path "${data}_ws/database.db" --odometry "$data/odometry.csv" \
        --image_timestamps "$data/image_timestamps.csv" --joint_adjustment on \
        --output_path "${data}_on" --overwrite > "$data.on.log" 2>&1
    fi
    if [ "${ROAD_STUDY_REPEAT:-0}" = 1 ]; then
      timed "$data.repeat" "$odomcal" "${run[@]}" --odometry "$data/odometry.csv" \
        --workspace_path "${data}_repeat" > "$data.repeat.log" 2>&1
    fi
    echo "$name: run exit $(cat "$data.run.exit") in $(cat "$data.run.seconds") s"
  done
done
