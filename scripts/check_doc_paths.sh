#!/usr/bin/env bash
# Checks that every repository path a document names in backquotes exists: a path is a
# backquoted word holding a slash and starting with one of the project's top-level folders or
# files. Prints each missing path; exits 1 when any is missing, 2 on bad usage.
#   scripts/check_doc_paths.sh docs/architecture.md [more.md ...]
set -euo pipefail
cd "$(dirname "$0")/.."
if [[ $# -eq 0 ]]; then
  echo "usage: scripts/check_doc_paths.sh FILE.md [FILE.md ...]" >&2
  exit 2
fi
missing=0
for doc in "$@"; do
  if [[ ! -f "$doc" ]]; then
    echo "$doc: no such file" >&2
    exit 2
  fi
  while IFS= read -r path; do
    # A folder written with a trailing slash, or a file.
    if [[ ! -e "${path%/}" ]]; then
      echo "$doc: names $path, which does not exist" >&2
      missing=1
    fi
  done < <(grep -o '`[^` ]*`' "$doc" | tr -d '`' |
           grep -E '^(refraster|harness|conformance|tool|tests|docs|scripts|examples|cmake|fuzz|\.ci)/' |
           grep -v '<' | sed -E 's/[.,:;]+$//' | sort -u)
done
exit "$missing"
