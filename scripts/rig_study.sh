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
  /usr/bin/python3 - "$@" <<'PY'
import json, sys
import numpy as np
data, ws, seconds, label = sys.argv[1:5]
truth = json.load(open(f"{data}/ground_truth.json"))
result = json.load(open(f"{ws}/calibration.json"))
def transform(t):
    w, x, y, z = t["quaternion_wxyz"]
    q = np.array([w, x, y, z])
    R = np.array([[1-2*(y*y+z*z), 2*(x*y-z*w), 2*(x*z+y*w)],
                  [2*(x*y+z*w), 1-2*(x*x+z*z), 2*(y*z-x*w)],
                  [2*(x*z-y*w), 2*(y*z+x*w), 1-2*(x*x+y*y)]])
    return R, np.array(t["translation_m"])
def angle(R):
    return np.degrees(np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1)))
truths = {c["name"]: transform(c["odom_from_cam"]) for c in truth["cameras"]}
print(f"{label}: {float(seconds):.0f} s")
for camera in result["cameras"]:
    name = camera["name"]
    if camera["status"] != "success":
        print(f"  {name:11s} {camera['status']}: {camera['reason'][:110]}")
        continue
    R, t = transform(camera["odom_from_cam"])
    Rt, tt = truths[name]
    e = 1000 * (t - tt)
    sd = camera["stddev"]
    print(f"  {name:11s} rotation {angle(Rt.T @ R):.3f} deg, x {e[0]:+.1f} y {e[1]:+.1f} "
          f"z {e[2]:+.1f} mm (z {camera['translation_z_source']}), "
          f"3 sigma x {3000*sd['translation_x_m']:.1f} y {3000*sd['translation_y_m']:.1f} mm")
for pair in result["camera_pairs"]:
    a, b = pair["camera_a"], pair["camera_b"]
    Ra, ta = truths[a]; Rb, tb = truths[b]
    R_true = Rb.T @ Ra; t_true = Rb.T @ (ta - tb)
    R, t = transform(pair["camb_from_cama"])
    # Left perturbation about camB's axes, and the translation in camB.
    E = R @ R_true.T
    psi = np.array([E[2, 1] - E[1, 2], E[0, 2] - E[2, 0], E[1, 0] - E[0, 1]])
    psi *= np.arccos(np.clip((np.trace(E) - 1) / 2, -1, 1)) / max(
        np.linalg.norm(psi), 1e-300)
    sd = pair["stddev"]
    r_sigmas = np.abs(psi) / np.radians(sd["rotation_axes_deg"])
    t_sigmas = np.abs(t - t_true) / np.array(sd["translation_m"])
    if pair["odom_offset_z_held"]:
        t_sigmas = t_sigmas[:0]  # the held heights' difference: not measured
    print(f"  {b}_from_{a}: rotation {angle(R_true.T @ R):.3f} deg, "
          f"translation {1000*np.linalg.norm(t - t_true):.1f} mm; "
          f"3 sigma rotation {3*max(sd['rotation_axes_deg']):.3f} deg; "
          f"largest error/sigma rotation {r_sigmas.max():.1f}"
          + (f", translation {t_sigmas.max():.1f}" if len(t_sigmas) else "")
          + (" (adjusted together)" if pair.get("adjusted_together") else ""))
PY
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
