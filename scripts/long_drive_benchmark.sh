#!/usr/bin/env bash
# Long drives (issue 18): renders the `long` preset cut to 100, 300 and 1000
# images, runs `odomcal run` on each, and prints per drive the time of every
# stage, the registered fraction, the part of the drive covered and the
# calibration error against the ground truth. With --plain_colmap, also plain
# COLMAP (feature_extractor, sequential_matcher with its default overlap,
# mapper) and `odomcal colmap` on its model, for the wall time and accuracy
# comparison. Minutes to hours on 2 cores; not part of CI.
#
#   scripts/long_drive_benchmark.sh [--odomcal build/plugin/odomcal]
#       [--out /tmp/odomcal_long] [--sizes "100 300 1000"] [--plain_colmap]
#       [--seed 1] [--run_flags "--matcher spatial"] [--plain_limit_s 2400]
#       [--plain_only]
# --plain_only: plain COLMAP only (implies --plain_colmap), e.g. after the
# odomcal runs, for a separate measurement on an idle machine.
# --plain_limit_s: stop plain COLMAP after this many seconds (0: never); its
# wall time is then a lower bound (plain COLMAP on 1000 images takes hours).
# --run_flags: more flags for `odomcal run` (e.g. to compare the matchers;
# give each variant its own --out). With "--joint_adjustment on" it also
# prints the joint and two-step errors per axis beside the stated sigma, and
# the metric model's camera centres against the render's (nothing but the
# calibration applied).
set -euo pipefail
export LC_ALL=C  # `time` prints decimal points, which the parser expects

odomcal=build/plugin/odomcal
scripts=$(dirname "$(realpath "$0")")  # colmap_images.py
out=/tmp/odomcal_long
sizes="100 300 1000"
plain=0
seed=1
run_flags=""
plain_limit=0
plain_only=0
while [[ $# -gt 0 ]]; do
  case "$1" in
    --odomcal) odomcal=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --sizes) sizes=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --plain_colmap) plain=1; shift ;;
    --run_flags) run_flags=$2; shift 2 ;;
    --plain_limit_s) plain_limit=$2; shift 2 ;;
    --plain_only) plain=1; plain_only=1; shift ;;
    *) echo "long_drive_benchmark.sh: error: unknown argument $1" >&2; exit 2 ;;
  esac
done
odomcal=$(realpath "$odomcal")
mkdir -p "$out"

# Rotation (deg) and translation (mm) error of calibration.json's
# odom_from_cam against the ground truth, the registered fraction and the
# covered duration.
summarize() {
  python3 - "$1" "$2" "$scripts" <<'PY'
import json, math, os, sys
if not os.path.exists(sys.argv[1]):
    sys.exit(print("no %s (see the log)" % sys.argv[1]))
result = json.load(open(sys.argv[1]))
truth = json.load(open(sys.argv[2]))["odom_from_cam"]
def quat_mul(a, b):
    w1, x1, y1, z1 = a; w2, x2, y2, z2 = b
    return [w1*w2 - x1*x2 - y1*y2 - z1*z2, w1*x2 + x1*w2 + y1*z2 - z1*y2,
            w1*y2 - x1*z2 + y1*w2 + z1*x2, w1*z2 + x1*y2 - y1*x2 + z1*w2]
estimate = result.get("odom_from_cam")
line = "status %s" % result["status"]
if estimate:
    q = estimate["quaternion_wxyz"]; t = truth["quaternion_wxyz"]
    d = quat_mul([q[0], -q[1], -q[2], -q[3]], t)
    angle = math.degrees(2 * math.atan2(math.sqrt(sum(c * c for c in d[1:])), abs(d[0])))
    dx = [a - b for a, b in zip(estimate["translation_m"][:2], truth["translation_m"][:2])]
    line += ", error %.3f deg, %.1f mm (x, y)" % (angle, 1000 * math.hypot(*dx))
colmap = result.get("colmap", {})
coverage = colmap.get("image_coverage")
if coverage:
    line += ", registered fraction %.3f (%d of %d), duration covered %.3f" % (
        colmap["registered_fraction"], coverage["num_in_calibration"],
        coverage["num_selected_images"], coverage["duration_fraction"])
print(line)
joint = result.get("joint_adjustment")
if estimate and joint:
    # Per axis against the stated sigma, joint and two-step side by side.
    def axes(transform):
        q = transform["quaternion_wxyz"]; t = truth["quaternion_wxyz"]
        d = quat_mul(q, [t[0], -t[1], -t[2], -t[3]])  # R_estimate R_true^T
        angle = 2 * math.atan2(math.sqrt(sum(c * c for c in d[1:])), d[0])
        norm = math.sqrt(sum(c * c for c in d[1:])) or 1.0
        rotation = [math.degrees(angle * c / norm) for c in d[1:]]
        return rotation + [1000 * (a - b) for a, b in
                           zip(transform["translation_m"][:2], truth["translation_m"][:2])]
    sd = result["stddev"]
    stated = sd["rotation_axes_deg"] + [1000 * sd["translation_x_m"], 1000 * sd["translation_y_m"]]
    errors = axes(estimate)
    # --joint_adjustment check keeps the two-step estimate unless the
    # adjustment contradicts it: then the result is the two-step's.
    label = "joint" if joint.get("adopted", True) else "check (two-step kept, max %.1f sigma)" % (
        joint.get("max_disagreement_sigmas") or 0.0)
    print("  %s %s in %.0f s (jackknife %.0f s): error rx ry rz %s deg, x y %s mm; stated sigma %s deg, %s mm" % (
        label, joint["status"], joint.get("time_s", 0.0), (joint.get("jackknife") or {}).get("time_s") or 0.0,
        " ".join("%+.4f" % e for e in errors[:3]), " ".join("%+.2f" % e for e in errors[3:]),
        " ".join("%.4f" % s for s in stated[:3]), " ".join("%.2f" % s for s in stated[3:])))
    two_step = result.get("diagnostics", {}).get("two_step")
    if two_step:
        errors = axes(two_step["odom_from_cam"])
        print("  two-step: error rx ry rz %s deg, x y %s mm" % (
            " ".join("%+.4f" % e for e in errors[:3]), " ".join("%+.2f" % e for e in errors[3:])))
    print("  largest scale change per stretch %s" % joint.get("max_scale_change"))
# The metric model's camera centres against the render's, nothing but the
# calibration applied.
sys.path.insert(0, sys.argv[3])
from colmap_images import camera_centres
truth_centres = {i["name"]: i["world_from_cam"]["translation_m"]
                 for i in json.load(open(sys.argv[2]))["images"]}
metric = os.path.join(os.path.dirname(sys.argv[1]), "sparse_metric")
distances = []
for model in sorted(os.listdir(metric)) if os.path.isdir(metric) else []:
    for name, centre in camera_centres(os.path.join(metric, model, "images.bin")).items():
        distances.append(math.dist(centre, truth_centres[name]))
if distances:
    names = sorted(truth_centres)
    path = sum(math.dist(truth_centres[a], truth_centres[b]) for a, b in zip(names, names[1:]))
    print("  metric model (%d models, %d images): camera centres against the truth rms %.1f mm, worst %.1f mm (%.3f %% of the %.1f m path)" % (
        len(os.listdir(metric)), len(distances), 1000 * math.sqrt(sum(d * d for d in distances) / len(distances)),
        1000 * max(distances), 100 * max(distances) / path, path))
PY
}

TIMEFORMAT="%R %U %S"
# "W s wall, C s CPU, w s/image wall" from a `time` output "wall user sys".
seconds() {
  python3 - "$1" "$2" <<'PY'
import sys
wall, user, system = map(float, open(sys.argv[1]).read().split()[-3:])
print("%.0f s wall, %.0f s CPU, %.2f s/image wall" % (wall, user + system, wall / int(sys.argv[2])))
PY
}

# Plain COLMAP in workspace $1 on the images in $2 with intrinsics $3.
plain_colmap() {
  colmap feature_extractor --database_path "$1/db.db" --image_path "$2" \
    --ImageReader.single_camera 1 --ImageReader.camera_model PINHOLE \
    --ImageReader.camera_params "$3" --SiftExtraction.use_gpu 0 \
    --SiftExtraction.max_num_features 2048 > "$1/extract.log" 2>&1
  colmap sequential_matcher --database_path "$1/db.db" --SiftMatching.use_gpu 0 \
    > "$1/match.log" 2>&1
  colmap mapper --database_path "$1/db.db" --image_path "$2" \
    --output_path "$1/sparse" --Mapper.ba_refine_focal_length 0 \
    --Mapper.ba_refine_principal_point 0 --Mapper.ba_refine_extra_params 0 \
    > "$1/map.log" 2>&1
}

for n in $sizes; do
  data="$out/long_$n"
  if [[ ! -f "$data/ground_truth.json" ]]; then
    "$odomcal" render --preset long --num_images "$n" --seed "$seed" \
      --output_path "$data" --overwrite > "$out/render_$n.log"
  fi
  # Intrinsics of the preset (ground_truth.json camera.params).
  params=$(python3 -c "import json,sys; print(','.join(str(p) for p in json.load(open(sys.argv[1]))['camera']['params']))" "$data/ground_truth.json")
  # Wall and CPU time (user + sys of all child processes: COLMAP's too). Both
  # grow on a loaded machine (waiting threads spin): measure on an idle one.
  if [[ $plain_only == 0 ]]; then
    { time "$odomcal" run --image_path "$data/images" --odometry "$data/odometry.csv" \
        --image_timestamps "$data/image_timestamps.csv" --camera_params "$params" \
        --workspace_path "$out/run_$n" $run_flags > "$out/run_$n.log" 2>&1 || true; } \
      2> "$out/run_$n.time"
    echo "== $n images: odomcal run $(seconds "$out/run_$n.time" "$n")"
    # The stage lines: "[k/5] title ... note (12.3 s)"; in a log (not a
    # terminal) COLMAP's progress lines come between title and "... note".
    grep -E '^\[[0-9]/[0-9]\]|^ +\.\.\. |^odomcal run:' "$out/run_$n.log" | cut -c1-160 |
      sed 's/^/  /' || true
    echo "  $(summarize "$out/run_$n/calibration.json" "$data/ground_truth.json")"
  else
    echo "== $n images"
  fi
  if [[ $plain == 1 ]]; then
    # odomcal never writes into an input folder: the calibration goes next
    # to the COLMAP workspace, not inside it.
    ws="$out/plain_$n"
    rm -rf "$ws" "${ws}_calibration"; mkdir -p "$ws/sparse"
    # timeout runs a program, not a shell function: the function's text
    # goes along to a new bash.
    # timeout puts COLMAP in a process group of its own, which a Ctrl-C on
    # the terminal does not reach: the trap passes it on (timeout forwards
    # the signal to its group).
    timeout "$plain_limit" bash -c "set -e; $(declare -f plain_colmap); plain_colmap \"\$@\"" \
      _ "$ws" "$data/images" "$params" &
    plain_pid=$!
    trap 'kill -TERM "$plain_pid" 2> /dev/null; exit 130' INT TERM
    rc=0
    { time wait "$plain_pid" || rc=$?; } 2> "$ws.time"
    trap - INT TERM
    last_log=$(ls -t "$ws"/*.log 2> /dev/null | head -1 || true)
    stage=${last_log##*/}
    if [[ $rc == 124 ]]; then
      echo "  plain COLMAP: stopped by --plain_limit_s after $(seconds "$ws.time" "$n") in $stage (its wall time is more: a lower bound)"
      continue
    elif [[ $rc != 0 ]]; then
      echo "  plain COLMAP: failed (exit $rc) in $stage after $(seconds "$ws.time" "$n")"
      continue
    fi
    "$odomcal" colmap --model_path "$ws/sparse" --database_path "$ws/db.db" \
      --odometry "$data/odometry.csv" --image_timestamps "$data/image_timestamps.csv" \
      --output_path "${ws}_calibration" > "${ws}_calibrate.log" 2>&1 || true
    echo "  plain COLMAP: $(seconds "$ws.time" "$n"); $(summarize "${ws}_calibration/calibration.json" "$data/ground_truth.json")"
  fi
done
