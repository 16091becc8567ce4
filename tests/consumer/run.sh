#!/usr/bin/env bash
# The project as a library, from the outside (ctest: consumer.installed_package):
#  1. `cmake --install` of the build into a fresh prefix;
#  2. examples/ configured as a project of its own with find_package(refraster), built and run
#     against that prefix: the core alone, a render whose hash is the golden one, a comparison
#     with OSMesa through the installed worker, a pixel's explanation;
#  3. the core built with pkg-config alone;
#  4. the core configured with REFRASTER_CORE_ONLY (no harness dependency looked for), built,
#     installed and consumed with COMPONENTS core.
# Usage: run.sh SOURCE_DIR BUILD_DIR WORK_DIR
set -euo pipefail
src=$1
build=$2
work=$3
rm -rf "$work"
mkdir -p "$work"
prefix=$work/prefix
step() { echo "== $*"; }
fail() { echo "FAILED: $*" >&2; exit 1; }

step "install $build into $prefix"
cmake --install "$build" --prefix "$prefix" >"$work/install.log"
for f in bin/refraster libexec/refraster/refraster-worker-osmesa include/refraster/renderer.hpp \
         include/harness/api.hpp; do
  [[ -e $prefix/$f ]] || fail "the installation lacks $f"
done
config=$(find "$prefix" -name refrasterConfig.cmake)
[[ -n $config ]] || fail "no refrasterConfig.cmake installed"
[[ -n $(find "$prefix" -name refrasterConfigVersion.cmake) ]] || fail "no version file"

step "the installed CLI finds its installed worker"
env -u REFRASTER_WORKER_DIR "$prefix/bin/refraster" compare \
  "$src/conformance/scenes/smoke/depth.json" --against osmesa || fail "installed refraster compare"

step "the installed CLI writes an EXR through its installed image codec module"
[[ -n $(find "$prefix" -name 'libharness_oiio_codec.so') ]] || fail "the installation lacks the codec module"
env -u REFRASTER_CODEC_DIR "$prefix/bin/refraster" render "$src/conformance/scenes/points/rgba32f.json" \
  -o "$work/points.exr" || fail "installed refraster render to .exr"
[[ -s $work/points.exr ]] || fail "no EXR written"

step "examples/ against the installed package"
cmake -S "$src/examples" -B "$work/examples" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" >"$work/examples-configure.log"
cmake --build "$work/examples" >"$work/examples-build.log"
out=$("$work/examples/core_triangle")
echo "$out"
grep -qx "28 pixels covered" <<<"$out" || fail "core_triangle"
scene=$src/conformance/scenes/textures/png_file.json
want=$(awk '$1 == "textures.png_file" {print $2}' "$src/conformance/expectations/ref-hashes.txt")
out=$("$work/examples/render_scene" "$scene" "$work/png_file.png" viewport_fma=on)
echo "$out"
grep -q "hash $want\$" <<<"$out" || fail "render_scene: want hash $want"
[[ -s $work/png_file.png ]] || fail "render_scene wrote no image"
# The worker comes from the package's refraster_WORKER_DIR, compiled into the example.
env -u REFRASTER_WORKER_DIR "$work/examples/compare_osmesa" \
  "$src/conformance/scenes/textures/sprite_lower_left_linear.json" || fail "compare_osmesa"
out=$("$work/examples/explain_pixel" "$src/conformance/scenes/textures/sprite_lower_left_linear.json" 8 8)
grep -q "covers the pixel" <<<"$out" || fail "explain_pixel: $out"
grep -q "point sprite coordinates" <<<"$out" || fail "explain_pixel: no sprite coordinates"

step "the core with pkg-config"
pcdir=$(dirname "$(find "$prefix" -name refraster.pc)")
# shellcheck disable=SC2046
c++ "$src/examples/core_triangle.cpp" $(PKG_CONFIG_PATH=$pcdir pkg-config --cflags --libs refraster) \
  -o "$work/core_triangle_pc"
"$work/core_triangle_pc" | grep -qx "28 pixels covered" || fail "pkg-config build"

step "the core alone (REFRASTER_CORE_ONLY)"
cmake -S "$src" -B "$work/core" -G Ninja -DCMAKE_BUILD_TYPE=Release -DREFRASTER_CORE_ONLY=ON \
  -DREFRASTER_BUILD_TESTS=OFF >"$work/core-configure.log"
if grep -E "^(OpenImageIO|nlohmann_json|simdjson|CLI11|glm|GTest|benchmark)_DIR:" \
     "$work/core/CMakeCache.txt"; then
  fail "configuring the core alone looked for a harness dependency"
fi
cmake --build "$work/core" >"$work/core-build.log"
cmake --install "$work/core" --prefix "$work/core-prefix" >/dev/null
[[ ! -e $work/core-prefix/include/harness ]] || fail "the core alone installed harness headers"
cmake -S "$src/tests/consumer/core_only" -B "$work/core-consumer" -G Ninja \
  -DCMAKE_PREFIX_PATH="$work/core-prefix" >"$work/core-consumer.log"
cmake --build "$work/core-consumer" >/dev/null
"$work/core-consumer/core_triangle" | grep -qx "28 pixels covered" || fail "core-only consumer"
echo "consumer: all steps passed"
