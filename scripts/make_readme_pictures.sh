#!/usr/bin/env bash
# Renders the README's pictures with headless Chromium from a real run: the report's index and
# a failing case's page (the suite's coverage squares under a flipped tie rule, so that
# something differs), and the explain view of that case's pixel. Writes docs/images/*.png.
# Usage: scripts/make_readme_pictures.sh   (after a build: build/bin/refraster)
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# A skips file, so that the report shows the inputs it records.
printf '# left out of the pictures\nsmoke\\.points$\n' >"$out/skips.txt"
REFRASTER_WORKER_DIR=build/bin build/bin/refraster conformance run \
  --cases 'smoke.*,triangles.coverage.square*,textures.sprite*' --skips "$out/skips.txt" \
  --profile-set tie_rule=right-top --output "$out/run" >/dev/null || true
shot() {  # URL OUT.png WIDTH,HEIGHT
  timeout 120 chromium --headless --no-sandbox --disable-gpu --no-first-run --hide-scrollbars \
    --user-data-dir="$out/chrome" --virtual-time-budget=2000 --window-size="$3" \
    --screenshot="$2" "$1" >/dev/null 2>&1
}
case_page=$out/run/cases/triangles.coverage.square_through_centres.html
shot "file://$out/run/index.html" docs/images/report-index.png 1200,1000
shot "file://$case_page#pixel=12,20" docs/images/report-case.png 1200,760
shot "file://$out/run/explain/triangles.coverage.square_through_centres.svg" \
  docs/images/explain-view.png 860,600
ls -l docs/images
