#!/usr/bin/env bash
# Installs missing dependencies, then configures and builds with the given preset (default dev).
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-dev}"
./scripts/setup-deps.sh
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset"
