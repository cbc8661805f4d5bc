#!/usr/bin/env bash
# clang-tidy (Debian's clang-tidy 14, .clang-tidy at the top) over every
# non-test source of solver/, adapters/, plugin/ and datasets/, as compiled
# in ${ODOMCAL_BUILD_DIR:-build}: configures that build directory with
# CMAKE_EXPORT_COMPILE_COMMANDS=ON (no build needed) and takes the sources
# from its compile_commands.json, leaving out those of the test targets.
#
# Each library target is read as one translation unit that includes all of
# its sources (<build>/tidy/<target>.cc, with the flags of the target's own
# compile command): clang-tidy spends most of its time matching inside
# Eigen's and Ceres' headers, once per translation unit, so one unit per
# target is about ten times faster than one per file. The price is the one
# of any unity build: two files of one target must not define the same name
# in an anonymous namespace (tidy then stops with "redefinition of ...").
#
# Exits non-zero on any finding (WarningsAsErrors) or a unit that does not
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
unity_dir="$build_dir/tidy"
rm -rf "$unity_dir"
mkdir -p "$unity_dir"
summary=$(python3 - "$build_dir/compile_commands.json" "$PWD" "$unity_dir" <<'PYTHON'
import collections, json, os, re, shlex, sys
database, root, unity_dir = sys.argv[1], os.path.realpath(sys.argv[2]), sys.argv[3]
unity_dir = os.path.realpath(unity_dir)
folders = re.compile(r"(solver|adapters|plugin|datasets)/")
target_of = re.compile(r"CMakeFiles/([^/]+)\.dir/")
targets = collections.defaultdict(dict)
for entry in json.load(open(database)):
    path = os.path.realpath(os.path.join(entry["directory"], entry["file"]))
    relative = os.path.relpath(path, root)
    command = entry.get("command") or " ".join(
        shlex.quote(a) for a in entry.get("arguments", []))
    output = entry.get("output") or command
    target = target_of.search(output)
    if (not folders.match(relative) or relative.endswith("_test.cc")
            or "_test.dir/" in output or target is None):
        continue
    targets[target.group(1)][path] = (entry["directory"], command, entry["file"])
units = []
for target, sources in sorted(targets.items()):
    unit = os.path.join(unity_dir, target + ".cc")
    with open(unit, "w") as out:
        out.write("// scripts/tidy.sh: every non-test source of %s.\n" % target)
        for path in sorted(sources):
            out.write('#include "%s"  // NOLINT(bugprone-suspicious-include)\n'
                      % path)
    directory, command, source = sources[min(sources)]
    arguments = shlex.split(command)
    arguments = [unit if a == source else a for a in arguments]
    units.append({"directory": directory, "file": unit,
                  "command": " ".join(shlex.quote(a) for a in arguments)})
json.dump(units, open(os.path.join(unity_dir, "compile_commands.json"), "w"),
          indent=1)
print(len(units), sum(len(s) for s in targets.values()))
PYTHON
)
read -r num_units num_files <<<"$summary"
if [ "$num_files" -eq 0 ]; then
  echo "tidy: no sources in $build_dir/compile_commands.json" >&2
  exit 1
fi
# The sources are included by absolute path, the headers through
# <build>/include/odomcal: both are this project's code.
root_pattern=$(printf '%s' "$PWD" | sed 's/[].[^$*+?(){}|\\]/\\&/g')
header_filter="^$root_pattern/(solver|adapters|plugin|datasets)/.*|.*/odomcal/(adapters|benchmarks|datasets|plugin|python|solver|tests)/.*"
start=$(date +%s)
status=0
"$run_clang_tidy" -clang-tidy-binary "$clang_tidy" -j "$jobs" -quiet \
  -p "$unity_dir" -header-filter="$header_filter" "$@" || status=$?
echo "tidy: $num_files files in $num_units translation units in" \
  "$(($(date +%s) - start)) s," \
  "$([ "$status" -eq 0 ] && echo 'no findings' || echo 'FINDINGS')"
if [ "$status" -ne 0 ]; then
  echo "tidy: findings above; a 'redefinition of' error among them means two files of one target define" \
       "the same name in an anonymous namespace; rename one (see the top of $0)" >&2
fi
exit "$status"
