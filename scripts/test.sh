#!/usr/bin/env bash
# Sets up, builds and runs every test (unit, osmesa, egl) with the CI preset.
# Extra arguments go to ctest, e.g. scripts/test.sh -L unit
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh ci
ctest --preset ci "$@"
