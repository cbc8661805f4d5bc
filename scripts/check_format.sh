#!/usr/bin/env bash
# CI job: every C++ file tracked by git matches .clang-format (Debian's
# clang-format 14). Fix with: git ls-files '*.h' '*.cc' | xargs clang-format -i
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install_deps.sh
mapfile -t files < <(git ls-files '*.h' '*.cc')
clang-format --dry-run --Werror "${files[@]}"
echo "check_format: ${#files[@]} files match .clang-format"
