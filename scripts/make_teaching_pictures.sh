#!/usr/bin/env bash
# Writes the pictures of docs/teaching.md: for each textbook algorithm, `refraster teach` on its
# teaching scene (examples/teach/), the algorithm's image, GL's and the difference mask as teach
# writes them (algorithm.png, gl.png, differences.png, 6 screen pixels a pixel), and a
# screenshot of two teaching pages in headless Chromium, and Bresenham's lecture frames (a step
# as SVG, the first 60 steps as an animated GIF). Writes docs/images/teach/.
# Usage: scripts/make_teaching_pictures.sh   (after a build: build/bin/refraster)
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
dest=docs/images/teach
mkdir -p "$dest"
while read -r algorithm scene; do
  build/bin/refraster teach "examples/teach/$scene.json" --algorithm "$algorithm" --zoom 6 \
    --output "$out/$algorithm" >/dev/null
  for image in algorithm gl differences; do
    cp "$out/$algorithm/$image.png" "$dest/$algorithm-$image.png"
  done
done <<'LIST'
dda lines_fan
bresenham lines_fan
midpoint lines_fan
wu lines_fan
circle circle_loops
scanline-evenodd arrow_polygon
scanline-nonzero star_evenodd
flood4 arrow_polygon
flood8 arrow_polygon
ear-clipping arrow_polygon
trapezoids arrow_polygon
painter bars_cycle
homogeneous behind_eye
half-space shared_edges
LIST
shot() {  # URL OUT.png WIDTH,HEIGHT
  timeout 120 chromium --headless --no-sandbox --disable-gpu --no-first-run --hide-scrollbars \
    --user-data-dir="$out/chrome" --virtual-time-budget=3000 --window-size="$3" \
    --screenshot="$2" "$1" >/dev/null 2>&1
}
shot "file://$out/bresenham/index.html#step=41&pixel=22,16" "$dest/page-bresenham.png" 1400,1000
shot "file://$out/scanline-evenodd/index.html#step=13&pixel=24,23" "$dest/page-scanline.png" \
  1400,1000
build/bin/refraster teach examples/teach/lines_fan.json --algorithm bresenham --zoom 6 \
  --frames --frame-steps 1-60 --output "$out/frames" >/dev/null
cp "$out/frames/frames/step-0041.svg" "$dest/frame-bresenham-step-0041.svg"
cp "$out/frames/frames/steps.gif" "$dest/frames-bresenham.gif"
ls -l "$dest"
