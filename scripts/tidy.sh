#!/usr/bin/env bash
# clang-tidy (.clang-tidy) over the C++ sources a change touches, with the build's compile
# commands (build/compile_commands.json: run scripts/build.sh first).
#   scripts/tidy.sh             the files changed since the previous commit (HEAD~1)
#   scripts/tidy.sh REF         the files changed since REF (a branch, a commit)
#   scripts/tidy.sh --all       every source file
# Prints each finding; exits 1 when a check listed in WarningsAsErrors fires, 2 on bad usage
# or a missing tool or build.
set -euo pipefail
cd "$(dirname "$0")/.."
tidy=$(command -v clang-tidy-14 || command -v clang-tidy || true)
if [[ -z "$tidy" ]]; then
  echo "tidy: clang-tidy-14 is not installed (scripts/setup-deps.sh installs it)" >&2
  exit 2
fi
if [[ ! -f build/compile_commands.json ]]; then
  echo "tidy: build/compile_commands.json is missing (run scripts/build.sh first)" >&2
  exit 2
fi
dirs=(refraster/src harness/src harness/workers conformance/runner/src tool)
if [[ "${1:-}" == "--all" ]]; then
  mapfile -t files < <(git ls-files "${dirs[@]}" | grep -E '\.cpp$' || true)
else
  base="${1:-HEAD~1}"
  if ! git rev-parse --verify --quiet "$base^{commit}" >/dev/null; then
    echo "tidy: no commit $base to compare with; nothing checked"
    exit 0
  fi
  mapfile -t files < <(git diff --name-only --diff-filter=d "$base" -- "${dirs[@]}" |
                       grep -E '\.cpp$' || true)
fi
# Only files the build compiles (a file of another platform's build is skipped).
checked=()
for f in "${files[@]}"; do
  if grep -q "\"file\": \"[^\"]*/$f\"" build/compile_commands.json; then checked+=("$f"); fi
done
if [[ ${#checked[@]} -eq 0 ]]; then
  echo "tidy: no changed C++ source to check"
  exit 0
fi
echo "tidy: ${#checked[@]} files"
status=0
for f in "${checked[@]}"; do
  "$tidy" -p build --quiet "$f" 2>/dev/null || status=1
done
exit "$status"
