#!/usr/bin/env bash
# The cost of a rig run: one rendered rig dataset (`odomcal render --rig`)
# through `odomcal run --rig`, through `odomcal run` once per camera on its
# own sub-folder, and through plain COLMAP on all its images (one camera per
# sub-folder, the sequential matcher with its default overlap as in
# scripts/long_drive_benchmark.sh --plain_colmap, the incremental mapper;
# what a user would run without odomcal, which calibrates nothing). Per step: wall time and
# peak resident memory (GNU time). docs/rigs.md quotes it.
#
#   scripts/rig_timing.sh DATA [STEPS (default "rig single colmap")]
#
# DATA: a folder written by `odomcal render --rig ...`. Needs
# build/plugin/odomcal, colmap and /usr/bin/time. Writes DATA.timing/ and
# prints one line per step.
set -euo pipefail
cd "$(dirname "$0")/.."
odomcal=$PWD/build/plugin/odomcal
data=${1:?usage: scripts/rig_timing.sh DATA [STEPS]}
steps=${2:-rig single colmap}
out=$data.timing
mkdir -p "$out"

# Wall seconds and peak resident MiB of a command, from GNU time's report.
measure() {  # label report command...
  local label=$1 report=$2
  shift 2
  /usr/bin/time -v -o "$report" "$@" > "$report.out" 2>&1 || true
  /usr/bin/python3 - "$label" "$report" <<'PY'
import re, sys
label, report = sys.argv[1:3]
text = open(report).read()
wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (\S+)", text).group(1)
seconds = 0.0
for part in wall.split(":"):
    seconds = seconds * 60 + float(part)
rss_kib = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", text).group(1))
status = re.search(r"Exit status: (\d+)", text).group(1)
print(f"{label}: {seconds:.0f} s, peak {rss_kib / 1024:.0f} MiB, exit {status}")
PY
}

# One --camera_params NAME=PARAMS per camera, from the render's cameras.txt.
camera_flags() {
  sed -n 's/^# \([A-Za-z0-9_.-]*\) (images.*--camera_params \(.*\)$/\1=\2/p' \
    "$data/cameras.txt"
}
cameras=$(camera_flags | cut -d= -f1)
num_images=$(find "$data/images" -name '*.png' | wc -l)
echo "$(basename "$data"): $(echo $cameras | wc -w) cameras, $num_images images, $(nproc) cores"

for step in $steps; do
  case $step in
    rig)
      flags=$(camera_flags | sed 's/^/--camera_params /' | tr '\n' ' ')
      rm -rf "$out/rig"
      measure "odomcal run --rig" "$out/rig.time" \
        "$odomcal" run --rig --image_path "$data/images" \
        --odometry "$data/odometry.csv" --camera_model PINHOLE $flags \
        --workspace_path "$out/rig"
      ;;
    single)
      for camera in $cameras; do
        params=$(camera_flags | sed -n "s/^$camera=//p")
        rm -rf "$out/single_$camera"
        measure "odomcal run, $camera alone" "$out/single_$camera.time" \
          "$odomcal" run --image_path "$data/images/$camera" \
          --odometry "$data/odometry.csv" --camera_model PINHOLE \
          --camera_params "$params" --workspace_path "$out/single_$camera"
      done
      ;;
    colmap)
      # Every camera's intrinsics are the same in the built-in rigs; COLMAP
      # takes one --ImageReader.camera_params for all folders.
      params=$(camera_flags | head -1 | cut -d= -f2)
      ws=$out/colmap
      rm -rf "$ws" && mkdir -p "$ws/sparse"
      cat > "$ws/run.sh" <<EOF
set -e
colmap feature_extractor --database_path $ws/database.db --image_path $data/images \
  --ImageReader.single_camera_per_folder 1 --ImageReader.camera_model PINHOLE \
  --ImageReader.camera_params $params --SiftExtraction.use_gpu 0 \
  --SiftExtraction.max_num_features 2048
colmap sequential_matcher --database_path $ws/database.db --SiftMatching.use_gpu 0
colmap mapper --database_path $ws/database.db --image_path $data/images \
  --output_path $ws/sparse
EOF
      measure "plain COLMAP (extract, sequential match, map)" "$out/colmap.time" \
        bash "$ws/run.sh"
      ;;
    *)
      echo "unknown step '$step' (rig, single, colmap)" >&2
      exit 2
      ;;
  esac
done
