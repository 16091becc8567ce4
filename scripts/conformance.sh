#!/usr/bin/env bash
# The main job: sets up, builds, and runs the conformance suite against OSMesa llvmpipe,
# writing results.jsonl and images to out/conformance/ (or $REFRASTER_OUT).
# Extra arguments go to `refraster conformance run`, e.g. --cases 'smoke.*'.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh dev
out="${REFRASTER_OUT:-out/conformance}"
exec build/bin/refraster conformance run --against osmesa --driver llvmpipe --output "$out" "$@"
