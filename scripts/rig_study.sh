#!/usr/bin/env bash
# A rig of three cameras that hardly overlap (`render --rig surround3`:
# front_left 5 Hz, rear 4 Hz, right 5 Hz, unsynchronised) through
# `odomcal run --rig`, per seed: every camera's extrinsic and every
# camera-to-camera transform against the truth, with the run's time; then
# the same drive with the rear camera capped. docs/rigs.md quotes it.
#
#   scripts/rig_study.sh [SEEDS (default "1 2 3")] [PRESET (default small)]
#
# RIG_STUDY_FLAGS adds flags to every run (e.g. "--joint_adjustment on": the
# cameras adjusted together), RIG_STUDY_SKIP_CAPPED=1 leaves out the capped
# drive. A rerun into the same workspace reuses its COLMAP stages. Needs
# build/plugin/odomcal (or $ODOMCAL) and colmap. Writes
# $RIG_STUDY_ROOT (default /tmp/odomcal_rig_study/).
set -euo pipefail
cd "$(dirname "$0")/.."
odomcal=${ODOMCAL:-$PWD/build/plugin/odomcal}
seeds=${1:-1 2 3}
preset=${2:-small}
root=${RIG_STUDY_ROOT:-/tmp/odomcal_rig_study}
mkdir -p "$root"

run_rig() {  # data_dir workspace
  local data=$1 ws=$2 flags=""
  # One --camera_params NAME=PARAMS per camera, from the render's cameras.txt.
  flags=$(sed -n 's/^# \([A-Za-z0-9_.-]*\) (images.*--camera_params \(.*\)$/--camera_params \1=\2/p' \
    "$data/cameras.txt" | tr '\n' ' ')
  local start=$(date +%s.%N)
  "$odomcal" run --rig --image_path "$data/images" --odometry "$data/odometry.csv" \
    --camera_model PINHOLE $flags ${RIG_STUDY_FLAGS:-} --workspace_path "$ws" \
    > "$ws.log" 2>&1 || true
  echo "$(date +%s.%N) - $start" | bc
}

evaluate() {  # data_dir workspace seconds label
  /usr/bin/python3 scripts/rig_errors.py "$@"
}

for seed in $seeds; do
  data=$root/${preset}_surround3_seed$seed
  [ -d "$data" ] || "$odomcal" render --preset "$preset" --rig surround3 --seed "$seed" \
    --output_path "$data" > /dev/null
  ws=$root/ws_${preset}_seed$seed
  seconds=$(run_rig "$data" "$ws")
  evaluate "$data" "$ws" "$seconds" "seed $seed"
done

[ "${RIG_STUDY_SKIP_CAPPED:-0}" = 1 ] && exit 0
seed=$(echo $seeds | cut -d' ' -f1)
data=$root/${preset}_surround3_capped_seed$seed
[ -d "$data" ] || "$odomcal" render --preset "$preset" --rig surround3 --seed "$seed" \
  --capped_camera rear --output_path "$data" > /dev/null
ws=$root/ws_${preset}_capped_seed$seed
seconds=$(run_rig "$data" "$ws")
evaluate "$data" "$ws" "$seconds" "seed $seed, rear camera capped"
