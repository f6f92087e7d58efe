#!/usr/bin/env bash
# Checks that every C++ and GLSL source is formatted as .clang-format says (clang-format from
# Debian 12); with --fix, formats them in place. CI runs the check: unformatted code fails it.
set -euo pipefail
cd "$(dirname "$0")/.."
mapfile -t files < <(git ls-files --cached --others --exclude-standard '*.cpp' '*.h' '*.comp' '*.glsl')
if [ "${1:-}" = "--fix" ]; then
  clang-format -i "${files[@]}"
else
  clang-format --dry-run --Werror "${files[@]}"
fi
