#!/usr/bin/env bash
# Sets up, builds and runs the tests with the CI preset: every label (unit, conformance,
# osmesa, egl) except the slow tier. The slow tier (label slow: the installed-package consumer
# test, which configures and builds the core again) runs with --slow; .ci/run runs both.
# Tests run one a core (ctest -j $(nproc)).
#   scripts/test.sh [--slow] [CTEST ARGS...]     e.g. scripts/test.sh -L unit
set -euo pipefail
cd "$(dirname "$0")/.."
tier=(-LE slow)
if [[ ${1:-} == --slow ]]; then
  tier=(-L slow)
  shift
fi
./scripts/build.sh ci
# One test a core (every test is bounded to 4 GB; two of the heaviest side by side fit the
# machine); a -j in CTEST ARGS comes later and wins.
ctest --preset ci -j "$(nproc)" "${tier[@]}" "$@"
