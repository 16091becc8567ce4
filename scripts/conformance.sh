#!/usr/bin/env bash
# The main job: sets up, builds, and renders the conformance scenes through OSMesa llvmpipe,
# writing the images under out/conformance/. Extra arguments select scene files or folders.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh dev
out=out/conformance
mkdir -p "$out"
targets=("$@")
[[ ${#targets[@]} -gt 0 ]] || targets=(conformance/scenes/smoke)
failed=0
while IFS= read -r scene; do
  rel="${scene#conformance/scenes/}"
  img="$out/${rel%.json}.png"
  mkdir -p "$(dirname "$img")"
  if build/bin/refraster render "$scene" --backend osmesa --driver llvmpipe -o "$img"; then :; else
    failed=$((failed + 1))
  fi
done < <(find "${targets[@]}" -name '*.json' | sort)
echo "images are in $out/ ($failed scene(s) failed)"
[[ $failed -eq 0 ]]
