#!/usr/bin/env bash
# The main job on a fresh machine: install dependencies, build, bake the
# default scene and render it headless. Prints where the image is.
set -euo pipefail
cd "$(dirname "$0")/.."

bash scripts/setup-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --target caustix-bake caustix-render caustix-inspect caustix-view

mkdir -p out
./build/bake/caustix-bake assets/scenes/default.json -o out/default.cxb -v
./build/runtime/caustix-render out/default.cxb -o out/default.png --size 1280x720 --time 2.0 -v
./build/runtime/caustix-render out/default.cxb -o out/default.exr --size 1280x720 --time 2.0 -q
echo
echo "image: $(pwd)/out/default.png   (linear float: $(pwd)/out/default.exr)"
