#!/usr/bin/env bash
# The floor plane on rendered scenes: renders each case, runs `odomcal run`
# on it (true intrinsics, no --fixed_translation_z_m) and prints translation
# z against the truth with its stated 3 sigma, the floor's roll and pitch
# against the true mount's, and the floor plane's status.
#
#   scripts/floor_plane_study.sh [WORK_DIR] [CASE ...]
#
# CASE is PRESET[:SEED][:RENDER_FLAGS] with commas for spaces in the flags,
# e.g. small:2 or small:1:--floor_slope_deg,2. Default: the presets default,
# small, tilted and hard, a floor sloped by 2 deg and an untextured floor.
# ODOMCAL is the odomcal binary (default build/plugin/odomcal).
set -euo pipefail
cd "$(dirname "$0")/.."
odomcal="${ODOMCAL:-build/plugin/odomcal}"
work="${1:-/tmp/odomcal_floor_study}"
shift || true
cases=("$@")
if [ ${#cases[@]} -eq 0 ]; then
  cases=(default:1 small:1 tilted:1 hard:1 "small:1:--floor_slope_deg,2"
         "small:1:--untextured_floor")
fi
mkdir -p "$work"
printf '%-40s %9s %9s %9s %9s %9s  %s\n' case z_err_mm 3sigma_mm \
  roll_err pitch_err status reason
for spec in "${cases[@]}"; do
  IFS=: read -r preset seed flags <<<"$spec"
  seed="${seed:-1}"
  flags="${flags//,/ }"
  name="${preset}_${seed}${flags:+_$(echo "$flags" | tr -c 'a-z0-9' '_')}"
  data="$work/$name/data"
  ws="$work/$name/ws"
  mkdir -p "$work/$name"
  if [ ! -f "$data/ground_truth.json" ]; then
    # shellcheck disable=SC2086
    "$odomcal" render --preset "$preset" --seed "$seed" --output_path "$data" \
      --overwrite $flags >"$work/$name/render.log" 2>&1
  fi
  params=$(/usr/bin/python3 -c "import json,sys; d=json.load(open(sys.argv[1])); \
print(d['camera']['model'], ','.join(repr(p) for p in d['camera']['params']))" \
    "$data/ground_truth.json")
  if [ ! -f "$ws/calibration.json" ]; then
    "$odomcal" run --image_path "$data/images" --odometry "$data/odometry.csv" \
      --image_timestamps "$data/image_timestamps.csv" \
      --camera_model "${params%% *}" --camera_params "${params#* }" \
      --workspace_path "$ws" >"$work/$name/run.log" 2>&1 || true
  fi
  /usr/bin/python3 - "$data/ground_truth.json" "$ws/calibration.json" "$spec" <<'PY'
import json, math, sys
truth = json.load(open(sys.argv[1]))
try:
    result = json.load(open(sys.argv[2]))
except (OSError, ValueError):
    print(f"{sys.argv[3]:40s} no result"); sys.exit(0)
w, x, y, z = truth["odom_from_cam"]["quaternion_wxyz"]
roll = math.degrees(math.atan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)))
pitch = math.degrees(math.asin(max(-1, min(1, 2 * (w * y - z * x)))))
z_true = truth["odom_from_cam"]["translation_m"][2]
z_est = result["odom_from_cam"]["translation_m"][2]
sigma = (result.get("stddev") or {}).get("translation_z_m")
floor = result.get("floor_plane") or {}
def err(a, b):
    return f"{(a - b + 180) % 360 - 180:9.3f}" if a is not None else f"{'-':>9}"
from_floor = result.get("translation_z_source") == "floor_plane"
z_text = f"{1000 * (z_est - z_true):9.2f} {3000 * sigma:9.2f}" if from_floor \
    else f"{'held':>9} {'-':>9}"
print(f"{sys.argv[3]:40s} {z_text} "
      f"{err(floor.get('floor_roll_deg'), roll)} "
      f"{err(floor.get('floor_pitch_deg'), pitch)} "
      f"{floor.get('status', '-'):>9}  {floor.get('translation_z_held_reason') or ''}")
PY
done
