#!/usr/bin/env bash
# Sets up, builds and runs the tests with the CI preset: every label (unit, conformance,
# osmesa, egl) except the slow tier. The slow tier (label slow: the installed-package consumer
# test, which configures and builds the core again) runs with --slow; .ci/run runs both.
#   scripts/test.sh [--slow] [CTEST ARGS...]     e.g. scripts/test.sh -L unit
set -euo pipefail
cd "$(dirname "$0")/.."
tier=(-LE slow)
if [[ ${1:-} == --slow ]]; then
  tier=(-L slow)
  shift
fi
./scripts/build.sh ci
ctest --preset ci "${tier[@]}" "$@"
