#!/usr/bin/env bash
# A COLMAP project of several cameras made by COLMAP itself, as a user
# without odomcal would make it, through `odomcal colmap`: a rendered rig
# (`odomcal render --rig`) mapped by plain COLMAP (one camera per image
# sub-folder, the sequential matcher, which matches across the cameras
# where their images are near in name order, the incremental mapper), then
# calibrated with the default joint adjustment check and with
# `--joint_adjustment on`; each camera and camera-to-camera transform
# against the truth (scripts/rig_errors.py). docs/rigs.md quotes it.
#
#   scripts/rig_project_study.sh [RIG (default stereo)] [SEED (default 5)] [PRESET (default small)]
#
# A rerun reuses the render and COLMAP's model. Needs build/plugin/odomcal
# (or $ODOMCAL) and colmap. Writes $RIG_PROJECT_STUDY_ROOT (default
# /tmp/odomcal_rig_project_study/).
set -euo pipefail
cd "$(dirname "$0")/.."
odomcal=${ODOMCAL:-$PWD/build/plugin/odomcal}
rig=${1:-stereo}
seed=${2:-5}
preset=${3:-small}
root=${RIG_PROJECT_STUDY_ROOT:-/tmp/odomcal_rig_project_study}
data=$root/${preset}_${rig}_seed$seed
ws=$data.colmap
mkdir -p "$root"

[ -d "$data" ] || "$odomcal" render --preset "$preset" --rig "$rig" --seed "$seed" \
  --output_path "$data" > /dev/null

if [ ! -d "$ws/sparse/0" ]; then
  # Every camera's intrinsics are the same in the built-in rigs; COLMAP takes
  # one --ImageReader.camera_params for all folders.
  params=$(sed -n 's/^# [A-Za-z0-9_.-]* (images.*--camera_params \(.*\)$/\1/p' \
    "$data/cameras.txt" | head -1)
  rm -rf "$ws" && mkdir -p "$ws/sparse"
  start=$(date +%s)
  {
    colmap feature_extractor --database_path "$ws/database.db" --image_path "$data/images" \
      --ImageReader.single_camera_per_folder 1 --ImageReader.camera_model PINHOLE \
      --ImageReader.camera_params "$params" --SiftExtraction.use_gpu 0 \
      --SiftExtraction.max_num_features 2048
    colmap sequential_matcher --database_path "$ws/database.db" --SiftMatching.use_gpu 0
    colmap mapper --database_path "$ws/database.db" --image_path "$data/images" \
      --output_path "$ws/sparse"
  } > "$ws.log" 2>&1
  echo "plain COLMAP: $(( $(date +%s) - start )) s, sub-models: $(ls "$ws/sparse" | tr '\n' ' ')"
fi

for use in check on; do
  out=$data.odomcal_$use
  start=$(date +%s.%N)
  "$odomcal" colmap --model_path "$ws/sparse" --database_path "$ws/database.db" \
    --odometry "$data/odometry.csv" --image_timestamps "$data/image_timestamps.csv" \
    --joint_adjustment "$use" --output_path "$out" --overwrite > "$out.log" 2>&1 || true
  seconds=$(echo "$(date +%s.%N) - $start" | bc)
  /usr/bin/python3 scripts/rig_errors.py "$data" "$out" "$seconds" \
    "odomcal colmap --joint_adjustment $use"
done
