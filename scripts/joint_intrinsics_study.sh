#!/usr/bin/env bash
# The joint adjustment with intrinsics COLMAP estimated (not given), held at
# COLMAP's values against refined (--joint_intrinsics held / auto).
#
#   scripts/joint_intrinsics_study.sh [PRESET] [SEEDS]     (small, "1 2 3")
#
# Per seed: `odomcal render`, `odomcal run` without --camera_params (COLMAP
# estimates and refines the intrinsics) and --joint_adjustment on, then
# `odomcal colmap` on that model and database with --joint_intrinsics held
# and auto. Prints per run the rotation error about the odometry's axes,
# x / y error, the largest error over its stated sigma, and the focal length
# before and after the adjustment. Work folder: $JOINT_INTRINSICS_STUDY_ROOT
# (default /tmp/odomcal_joint_intrinsics_study).
set -euo pipefail
cd "$(dirname "$0")/.."
odomcal=${ODOMCAL:-$PWD/build/plugin/odomcal}
preset=${1:-small}
seeds=${2:-1 2 3}
root=${JOINT_INTRINSICS_STUDY_ROOT:-/tmp/odomcal_joint_intrinsics_study}
mkdir -p "$root"
for seed in $seeds; do
  data=$root/${preset}_$seed
  [ -d "$data" ] || "$odomcal" render --preset "$preset" --seed "$seed" \
    --output_path "$data" > /dev/null
  track=$(/usr/bin/python3 -c "import json; print(json.load(open('$data/ground_truth.json'))['odometry_noise']['wheel_base_m'])")
  timing=(--odometry "$data/odometry.csv" --image_timestamps "$data/image_timestamps.csv"
          --wheel_track_m "$track")
  if [ ! -f "$data.ws/calibration.json" ]; then
    "$odomcal" run --image_path "$data/images" --workspace_path "$data.ws" \
      --joint_adjustment on "${timing[@]}" > "$data.ws.log" 2>&1 || true
  fi
  database=$(find "$data.ws/" -name database.db | head -1)
  for use in held auto; do
    "$odomcal" colmap --model_path "$data.ws/sparse" --database_path "$database" \
      --joint_adjustment on --joint_intrinsics "$use" "${timing[@]}" \
      --output_path "$data.$use" --overwrite > "$data.$use.log" 2>&1 || true
    /usr/bin/python3 - "$data" "$data.$use" "$preset $seed $use" <<'PY'
import json, sys
sys.path.insert(0, "scripts")
from calibration_errors import errors_and_sigmas
data, out, label = sys.argv[1:4]
truth = json.load(open(f"{data}/ground_truth.json"))["odom_from_cam"]
result = json.load(open(f"{out}/calibration.json"))
found = errors_and_sigmas(result, truth)
if found is None:
    print(f"{label}: {result['status']}: {result.get('message', '')[:100]}")
    sys.exit()
e, sd = found
worst = max(abs(a) / b for a, b in zip(e[:5], sd[:5]) if b)
line = (f"{label}: rotation {' '.join('%+.4f' % v for v in e[:3])} deg, "
        f"x / y {1e3 * e[3]:+.2f} / {1e3 * e[4]:+.2f} mm, largest error/sigma {worst:.1f}")
for camera in (result.get("joint_adjustment") or {}).get("camera_intrinsics") or []:
    line += (f"; focal {camera['params_before'][0]:.2f} -> {camera['params'][0]:.2f} px"
             f" ({'refined' if camera['refined'] else 'held'})")
print(line)
PY
  done
done
