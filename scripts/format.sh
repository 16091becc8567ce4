#!/usr/bin/env bash
# The sources' layout is .clang-format's, as clang-format 14 (Debian 12) writes it.
#   scripts/format.sh          rewrites every tracked C++ file in place
#   scripts/format.sh --check  changes nothing; lists the files that differ, exit 1 if any
set -euo pipefail
cd "$(dirname "$0")/.."
format=$(command -v clang-format-14 || command -v clang-format || true)
if [[ -z "$format" ]]; then
  echo "format: clang-format-14 is not installed (scripts/setup-deps.sh installs it)" >&2
  exit 2
fi
mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h')
if [[ "${1:-}" == "--check" ]]; then
  bad=()
  for f in "${files[@]}"; do
    "$format" --dry-run --Werror "$f" >/dev/null 2>&1 || bad+=("$f")
  done
  if [[ ${#bad[@]} -gt 0 ]]; then
    printf 'format: not as .clang-format lays it out (run scripts/format.sh): %s\n' "${bad[@]}" >&2
    exit 1
  fi
  echo "format: ${#files[@]} files as .clang-format lays them out"
else
  "$format" -i "${files[@]}"
fi
