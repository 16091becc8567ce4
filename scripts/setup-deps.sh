#!/usr/bin/env bash
# Installs the Debian 12 packages refraster builds and runs with. Idempotent: when every
# package is present it installs nothing and does not touch the network.
#   scripts/setup-deps.sh        what the build, the tests and the conformance run need
#   scripts/setup-deps.sh fuzz   what the fuzz preset needs (scripts/fuzz.sh): clang,
#                                libFuzzer's runtime and the two header libraries
set -euo pipefail

if [[ "${1:-}" == "fuzz" ]]; then
  packages=(
    cmake ninja-build git
    # clang 14 and its runtime libraries (libFuzzer, ASan, UBSan); g++ brings libstdc++
    clang-14 libclang-rt-14-dev g++
    nlohmann-json3-dev libsimdjson-dev libglm-dev
  )
else
packages=(
  # toolchain; clang-format-14 checks the sources' layout (scripts/format.sh)
  g++ cmake ninja-build pkg-config git clang-format-14
  # clang-tidy-14 checks the changed sources (scripts/tidy.sh, .clang-tidy)
  clang-tidy-14
  # libraries (harness and tests)
  nlohmann-json3-dev libsimdjson-dev libcli11-dev libglm-dev libgtest-dev libgmock-dev libbenchmark-dev
  # the tests read the batch-system examples' YAML (docs/examples/)
  libyaml-cpp-dev
  # image files; OpenImageIO's exported CMake targets name the tools' binaries, so both
  libopenimageio-dev openimageio-tools
  # texture files are decoded with libpng alone
  libpng-dev
  # Mesa: OSMesa, and EGL surfaceless with the llvmpipe/softpipe DRI driver
  libosmesa6-dev libegl-dev libopengl-dev libegl-mesa0 libgl1-mesa-dri
  # zink (--driver zink: GL on Vulkan) runs on lavapipe, Mesa's software Vulkan driver
  mesa-vulkan-drivers
  # the HTML report test opens the report in headless Chromium
  chromium
)
fi

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [[ "$status" == "install ok installed" ]] || missing+=("$p")
done

if [[ ${#missing[@]} -eq 0 ]]; then
  echo "setup-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "setup-deps: installing ${missing[*]}"
sudo=""
if [[ $(id -u) -ne 0 ]]; then
  command -v sudo >/dev/null || { echo "setup-deps: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq "${missing[@]}" >/dev/null
echo "setup-deps: done"
