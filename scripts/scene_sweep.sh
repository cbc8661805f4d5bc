#!/usr/bin/env bash
# Rendered scenes varied beyond the presets (camera height, pitch, mount
# direction, drive length, odometry noise, resolution, texture, floors that
# are not level or not textured), each through `odomcal run` for its COLMAP model and then
# `odomcal colmap` on that model with `--joint_adjustment off` (the two-step
# calibration), `check` (the default) and `on`, the robot's wheel track
# given: per scene and parameter the error and the stated sigma.
# SWEEP_SKIP_RUN=1 keeps a scene's existing model (`odomcal colmap` only).
# docs/joint_adjustment.md quotes the table.
#
#   scripts/scene_sweep.sh [FIRST_SCENE (default 1)] [LAST_SCENE (default 29)]
#
# Needs build/plugin/odomcal and colmap; about 2 min per scene on 2 cores.
# Writes /tmp/odomcal_scene_sweep/ and prints one line per scene and method.
set -euo pipefail
cd "$(dirname "$0")/.."
odomcal=$PWD/build/plugin/odomcal
root=/tmp/odomcal_scene_sweep
mkdir -p "$root"
first=${1:-1}
last=${2:-29}

# name|preset|seed|render flags (mount: YAW,PITCH_DOWN,ROLL,X,Y,Z)
scenes=(
  "forward_s1|small|1|"
  "forward_s2|small|2|"
  "forward_s3|small|3|"
  "forward_64|default|1|"
  "left_0.6m_10down_s1|small|1|--camera_mount 90,10,0,0.05,0.15,0.6"
  "left_0.6m_10down_s2|small|2|--camera_mount 90,10,0,0.05,0.15,0.6"
  "rear_0.5m_15down_s1|small|1|--camera_mount 180,15,0,-0.2,0.0,0.5"
  "rear_0.5m_15down_s2|small|2|--camera_mount 180,15,0,-0.2,0.0,0.5"
  "forward_1.2m_30down|small|4|--camera_mount 0,30,0,0.2,0.0,1.2"
  "forward_0.2m_level|small|5|--camera_mount 0,0,0,0.25,-0.05,0.2"
  "forward_0.8m_20down|small|6|--camera_mount 0,20,0,0.15,0.05,0.8"
  "rolled_90_tilted|tilted|1|"
  "short_30|small|7|--num_images 30"
  "long_120|default|2|--num_images 120"
  "hard_noisy_offset|hard|1|"
  "slope_1deg|small|8|--floor_slope_deg 1"
  "untextured_floor|small|9|--untextured_floor"
  "right_0.4m_5down|small|10|--camera_mount -90,5,2,0.0,-0.2,0.4"
  "yaw20_0.45m|small|11|--camera_mount 20,12,0,0.15,0.1,0.45"
  "rear_1.0m_30down|small|12|--camera_mount 180,30,0,-0.15,0.05,1.0"
  "forward_s4|small|13|"
  "forward_s5|small|14|"
  "left_1.5m_25down|default|3|--camera_mount 80,25,0,0.0,0.2,1.5"
  "res_640x480|small|15|--image_size 640x480"
  "res_1280x720|small|16|--image_size 1280x720"
  "sparse_texture|small|17|--texture sparse"
  "repetitive_texture|small|18|--texture repetitive"
  "odometry_10hz|small|19|--odometry_rate_hz 10"
  "long_300|default|4|--num_images 300"
)

evaluate() {  # name method data result seconds
  /usr/bin/python3 - "$@" <<'PY'
import json, math, sys
name, method, data, path, seconds = sys.argv[1:6]
truth = json.load(open(f"{data}/ground_truth.json"))["odom_from_cam"]
try:
    r = json.load(open(path))
except (OSError, ValueError) as error:
    print(f"{name:22s} {method:8s} no result ({error})")
    sys.exit()
def rpy(q):
    w, x, y, z = q
    R = [[1-2*(y*y+z*z), 2*(x*y-z*w), 2*(x*z+y*w)],
         [2*(x*y+z*w), 1-2*(x*x+z*z), 2*(y*z-x*w)],
         [2*(x*z-y*w), 2*(y*z+x*w), 1-2*(x*x+y*y)]]
    return R
def angle_error_axes(qe, qt):
    # truth = Exp(e) * estimate: e in the odometry frame, degrees
    Re, Rt = rpy(qe), rpy(qt)
    D = [[sum(Rt[i][k]*Re[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    c = max(-1.0, min(1.0, (D[0][0]+D[1][1]+D[2][2]-1)/2)); a = math.acos(c)
    if a < 1e-12: return [0.0, 0.0, 0.0]
    s = a / (2*math.sin(a))
    return [math.degrees(s*(D[2][1]-D[1][2])), math.degrees(s*(D[0][2]-D[2][0])),
            math.degrees(s*(D[1][0]-D[0][1]))]
status = r["status"]
if r.get("odom_from_cam") is None or r["odom_from_cam"].get("quaternion_wxyz") is None:
    print(f"{name:22s} {method:8s} {status} {float(seconds):5.0f} s: {r.get('message','')[:90]}")
    sys.exit()
e = angle_error_axes(r["odom_from_cam"]["quaternion_wxyz"], truth["quaternion_wxyz"])
sd = r["stddev"]
sr = sd["rotation_axes_deg"]  # about the odometry's axes, as e
t = r["odom_from_cam"]["translation_m"]; tt = truth["translation_m"]
dt = [1000*(t[k]-tt[k]) for k in range(3)]
st = [1000*v if v is not None else float("nan")
      for v in (sd["translation_x_m"], sd["translation_y_m"], sd["translation_z_m"])]
cells = []
for label, err, sig in zip(["rx", "ry", "rz"], e, sr):
    cells.append(f"{label} {err:+.3f}/{sig:.3f}")
for label, err, sig in zip(["x", "y", "z"], dt, st):
    cells.append(f"{label} {err:+.1f}/{sig:.1f}")
z = r.get("translation_z_source")
print(f"{name:22s} {method:8s} {status} {float(seconds):5.0f} s  deg: {' '.join(cells[:3])}  mm: {' '.join(cells[3:])}  z {z}")
PY
}

for ((k = first; k <= last; ++k)); do
  IFS='|' read -r name preset seed flags <<< "${scenes[k-1]}"
  data=$root/$name/data
  ws=$root/$name/ws
  if [ ! -f "$data/ground_truth.json" ]; then
    if ! "$odomcal" render --preset "$preset" --seed "$seed" $flags --overwrite \
      --output_path "$data" > "$root/$name.render.log" 2>&1; then
      echo "$name: render refused: $(tail -1 "$root/$name.render.log")"
      continue
    fi
  fi
  params=$(/usr/bin/python3 -c "import json,sys; c=json.load(open(sys.argv[1]))['camera']; print(c['model'], ','.join('%.17g' % v for v in c['params']))" "$data/ground_truth.json")
  model=${params% *}; values=${params#* }
  # The robot's nominal wheel track, as its user would give it: without it
  # unequal wheels shift y (docs/systematics.md), which the run names.
  track=$(/usr/bin/python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['odometry_noise']['wheel_base_m'])" "$data/ground_truth.json")
  if [ "${SWEEP_SKIP_RUN:-0}" != 1 ] || [ ! -d "$ws/sparse" ]; then
    "$odomcal" run --image_path "$data/images" --odometry "$data/odometry.csv" \
      --image_timestamps "$data/image_timestamps.csv" --camera_model "$model" \
      --camera_params "$values" --wheel_track_m "$track" --joint_adjustment off \
      --workspace_path "$ws" > "$root/$name/run.log" 2>&1 || true
  fi
  # The three uses of the joint adjustment on the run's COLMAP model.
  for method in off check on; do
    start=$(date +%s.%N)
    "$odomcal" colmap --model_path "$ws/sparse" --database_path "$ws/database.db" \
      --odometry "$data/odometry.csv" --image_timestamps "$data/image_timestamps.csv" \
      --wheel_track_m "$track" --joint_adjustment "$method" \
      --output_path "$root/$name/$method" --overwrite > "$root/$name/$method.log" 2>&1 || true
    seconds=$(echo "$(date +%s.%N) - $start" | bc)
    evaluate "$name" "$method" "$data" "$root/$name/$method/calibration.json" "$seconds"
  done
done
