#!/usr/bin/env bash
# Runs the three studies of docs/precision-study.md at their default sizes (minutes each) and
# copies their figures and summaries to docs/images/study/: precision.svg, antialiasing.svg,
# stability.svg and the matching *-summary.md. The tables go to out/study/<name>/study.csv.
# Usage: scripts/make_study_figures.sh [--seed N]   (after a build: build/bin/refraster)
set -euo pipefail
cd "$(dirname "$0")/.."
dest=docs/images/study
mkdir -p "$dest"
for study in precision antialiasing stability; do
  echo "== $study"
  build/bin/refraster study "$study" --output "out/study/$study" --quiet "$@"
  cp "out/study/$study/study.svg" "$dest/$study.svg"
  cp "out/study/$study/summary.md" "$dest/$study-summary.md"
done
