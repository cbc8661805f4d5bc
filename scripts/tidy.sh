#!/usr/bin/env bash
# clang-tidy (Debian's clang-tidy 14, .clang-tidy at the top) over every
# non-test source of solver/, adapters/, plugin/ and datasets/, as compiled
# in ${ODOMCAL_BUILD_DIR:-build}: configures that build directory with
# CMAKE_EXPORT_COMPILE_COMMANDS=ON (no build needed) and takes the sources
# from its compile_commands.json, leaving out those of the test targets.
# Exits non-zero on any finding (WarningsAsErrors) or a file that does not
# compile. Extra arguments go to run-clang-tidy (e.g. -fix).
#   ODOMCAL_BUILD_DIR=build ODOMCAL_JOBS=2 scripts/tidy.sh
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${ODOMCAL_BUILD_DIR:-build}"
jobs="${ODOMCAL_JOBS:-$(nproc)}"

find_tool() {
  local name
  for name in "$@"; do
    if command -v "$name" >/dev/null; then
      command -v "$name"
      return 0
    fi
  done
  echo "tidy: none of $* found (apt-get install clang-tidy)" >&2
  return 1
}
clang_tidy=$(find_tool clang-tidy-14 clang-tidy)
run_clang_tidy=$(find_tool run-clang-tidy-14 run-clang-tidy)

cmake -S . -B "$build_dir" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON >/dev/null
# Sources of solver/, adapters/, plugin/ and datasets/ (any depth) that a
# library or the odomcal executable compiles: not *_test.cc, nor the test
# helpers compiled only into a *_test target.
mapfile -t files < <(python3 - "$build_dir/compile_commands.json" "$PWD" <<'EOF'
import json, os, re, sys
database, root = sys.argv[1], os.path.realpath(sys.argv[2])
folders = re.compile(r"(solver|adapters|plugin|datasets)/")
files = set()
for entry in json.load(open(database)):
    path = os.path.realpath(os.path.join(entry["directory"], entry["file"]))
    relative = os.path.relpath(path, root)
    output = entry.get("output") or entry.get("command") or " ".join(
        entry.get("arguments", []))
    if (folders.match(relative) and not relative.endswith("_test.cc")
            and "_test.dir/" not in output):
        files.add(path)
print("\n".join(sorted(files)))
EOF
)
if [ "${#files[@]}" -eq 0 ]; then
  echo "tidy: no sources in $build_dir/compile_commands.json" >&2
  exit 1
fi
# run-clang-tidy takes regular expressions: anchor each path.
patterns=()
for file in "${files[@]}"; do
  patterns+=("^$(printf '%s' "$file" | sed 's/[].[^$*+?(){}|\\]/\\&/g')\$")
done
start=$(date +%s)
status=0
"$run_clang_tidy" -clang-tidy-binary "$clang_tidy" -j "$jobs" -quiet \
  -p "$build_dir" "$@" "${patterns[@]}" || status=$?
echo "tidy: ${#files[@]} files in $(($(date +%s) - start)) s," \
  "$([ "$status" -eq 0 ] && echo 'no findings' || echo 'FINDINGS')"
exit "$status"
