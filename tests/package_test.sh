#!/usr/bin/env bash
# The installed package as its users meet it: `cmake --install` into a
# temporary prefix, then examples/pool_floor (a copy, built with Ninja and
# with Makefiles) against that prefix only: caustix_bake() bakes its scene,
# its ctest checks the floor against flat-water physics; then incremental
# builds re-bake exactly when the scene or its mesh changes;
# examples/deferred_lights (a G-buffer renderer lighting every receiver from
# two lights in one pass) checks its pixels against physics; and a program
# built with pkg-config alone links the runtime.
# Usage: package_test.sh <build dir> <source dir>
set -euo pipefail
build=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export MESA_SHADER_CACHE_DISABLE=true

cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
for f in bin/caustix-bake bin/caustix-render bin/caustix-inspect include/caustix/runtime/engine.h \
         include/caustix/runtime/caustix.glsl include/caustix/common/version.h lib/libcaustix_runtime.a \
         lib/cmake/caustix/caustixConfig.cmake lib/pkgconfig/caustix.pc; do
  [[ -f "$tmp/prefix/$f" ]] || { echo "not installed: $f"; exit 1; }
done
# The runtime's internals and the sample renderer are not part of the package.
for f in include/caustix/runtime/gl_objects.h include/caustix/runtime/renderer.h include/caustix/sample; do
  [[ ! -e "$tmp/prefix/$f" ]] || { echo "installed, but not public: $f"; exit 1; }
done

mtime() { stat -c %.9Y "$1"; }
for gen in Ninja "Unix Makefiles"; do
  echo "== examples/pool_floor with $gen"
  ex="$tmp/src-${gen// /_}"
  out="$tmp/build-${gen// /_}"
  cp -r "$src/examples/pool_floor" "$ex"
  cmake -S "$ex" -B "$out" -G "$gen" -DCMAKE_PREFIX_PATH="$tmp/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$out" >/dev/null
  (cd "$out" && ctest --output-on-failure)
  cxb="$out/pool.cxb"
  first=$(mtime "$cxb")
  # Nothing changed: no re-bake.
  cmake --build "$out" >/dev/null
  [[ $(mtime "$cxb") == "$first" ]] || { echo "$gen: re-baked with nothing changed"; exit 1; }
  # An unrelated source changed: the program rebuilds, the asset does not.
  sleep 1; touch "$ex/main.cpp"
  cmake --build "$out" >/dev/null
  [[ $(mtime "$cxb") == "$first" ]] || { echo "$gen: re-baked when only main.cpp changed"; exit 1; }
  # The mesh the scene names changed (the depfile knows it): re-bake.
  sleep 1; touch "$ex/scene/plane.obj"
  cmake --build "$out" >/dev/null
  second=$(mtime "$cxb")
  [[ "$second" != "$first" ]] || { echo "$gen: no re-bake after the mesh changed"; exit 1; }
  # The scene changed: re-bake.
  sleep 1; touch "$ex/scene/pool.json"
  cmake --build "$out" >/dev/null
  [[ $(mtime "$cxb") != "$second" ]] || { echo "$gen: no re-bake after scene.json changed"; exit 1; }
  echo "$gen: incremental re-bakes as expected"
done

echo "== examples/deferred_lights with Ninja"
cp -r "$src/examples/deferred_lights" "$tmp/src-deferred"
cmake -S "$tmp/src-deferred" -B "$tmp/build-deferred" -G Ninja -DCMAKE_PREFIX_PATH="$tmp/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$tmp/build-deferred" >/dev/null
(cd "$tmp/build-deferred" && ctest --output-on-failure)

echo "== pkg-config"
export PKG_CONFIG_PATH="$tmp/prefix/lib/pkgconfig"
cat > "$tmp/version.cpp" <<'CPP'
#include <cstdio>
#include "caustix/runtime/engine.h"
#include "caustix/runtime/version.h"
int main() { std::printf("%s %d\n", caustix::version(), CAUSTIX_VERSION_MAJOR); return caustix::runtime::glsl_include_source()[0] ? 0 : 1; }
CPP
# shellcheck disable=SC2046
g++ -o "$tmp/version" "$tmp/version.cpp" $(pkg-config --cflags --libs caustix)
"$tmp/version"
echo "package: OK"
