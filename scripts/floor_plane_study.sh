#!/usr/bin/env bash
# The floor plane on rendered scenes: renders each case, runs `odomcal run`
# on it (true intrinsics, no --fixed_translation_z_m) and prints translation
# z against the truth with its stated 3 sigma, the error of the floor's roll
# and pitch (tilt_err, deg: the angle between the odometry's up seen from the
# camera under the floor's rotation and under the true mount's), and the
# floor plane's status.
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
printf '%-40s %9s %9s %9s %9s  %s\n' case z_err_mm 3sigma_mm tilt_err \
  status reason
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
def rotate(q, v):  # q = (w, x, y, z) applied to v
    w, x, y, z = q
    u = (x, y, z)
    c = (u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0])
    c2 = (u[1] * c[2] - u[2] * c[1], u[2] * c[0] - u[0] * c[2], u[0] * c[1] - u[1] * c[0])
    return tuple(v[i] + 2 * (w * c[i] + c2[i]) for i in range(3))
def conj(q):
    return (q[0], -q[1], -q[2], -q[3])
def mul(a, b):
    w1, x1, y1, z1 = a; w2, x2, y2, z2 = b
    return (w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
            w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2)
def exp(phi):
    angle = math.sqrt(sum(p * p for p in phi))
    if angle == 0:
        return (1.0, 0.0, 0.0, 0.0)
    s = math.sin(angle / 2) / angle
    return (math.cos(angle / 2), phi[0] * s, phi[1] * s, phi[2] * s)
z_true = truth["odom_from_cam"]["translation_m"][2]
z_est = result["odom_from_cam"]["translation_m"][2]
sigma = (result.get("stddev") or {}).get("translation_z_m")
floor = result.get("floor_plane") or {}
from_floor = result.get("translation_z_source") == "floor_plane"
z_text = f"{1000 * (z_est - z_true):9.2f} {3000 * sigma:9.2f}" if from_floor \
    else f"{'held':>9} {'-':>9}"
tilt = f"{'-':>9}"
if "roll_pitch_correction_deg" in floor:
    phi = [math.radians(v) for v in floor["roll_pitch_correction_deg"]] + [0.0]
    q = mul(exp(phi), tuple(result["odom_from_cam"]["quaternion_wxyz"]))
    a = rotate(conj(q), (0, 0, 1))
    b = rotate(conj(tuple(truth["odom_from_cam"]["quaternion_wxyz"])), (0, 0, 1))
    dot = max(-1.0, min(1.0, sum(x * y for x, y in zip(a, b))))
    tilt = f"{math.degrees(math.acos(dot)):9.3f}"
print(f"{sys.argv[3]:40s} {z_text} {tilt} "
      f"{floor.get('status', '-'):>9}  {floor.get('translation_z_held_reason') or ''}")
PY
done
