#!/usr/bin/env bash
# Regenerates docs/gallery/: every canonical scene (and assets/demo/'s) baked with the defaults
# and rendered by caustix-render at 640 x 400 (2x supersampled, filmic at
# -1 EV) from its own camera and, for scenes with water, from under the
# water looking up across it; docs/gallery.md shows them. Needs a built
# tree. About five minutes on 2 cores with llvmpipe.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build
B=build
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
mkdir -p docs/gallery
for json in assets/scenes/*.json; do
  s=$(basename "$json" .json)
  $B/bake/caustix-bake "$json" -o "$T/$s.cxb" -q
  if [ "$s" = default ]; then
    # The README's picture (default_before.png is the scene before it had textures and a sky, kept as it was).
    $B/runtime/caustix-render "$T/$s.cxb" -o docs/gallery/default_after.png --size 960x540 --time 2.0 -q
    continue
  fi
  $B/runtime/caustix-render "$T/$s.cxb" -o "docs/gallery/${s}_above.png" --size 640x400 -q
  # Under the water: a third of the way from the target to the camera,
  # 0.35 m below the rest level, looking across the pool and a little
  # down (the surface, seen from below, fills the top of the frame).
  below=$(/usr/bin/python3 - "$json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
w, c = d.get("water"), d.get("camera", {})
if w:
    p, t, y = c["position"], c["target"], w["level"]
    print(f"{t[0] + (p[0] - t[0]) / 3:.3f},{y - 0.35:.3f},{t[2] + (p[2] - t[2]) / 3:.3f} "
          f"{t[0] - 0.6 * (p[0] - t[0]):.3f},{y - 1.0:.3f},{t[2] - 0.6 * (p[2] - t[2]):.3f}")
PY
)
  if [ -n "$below" ]; then
    set -- $below
    $B/runtime/caustix-render "$T/$s.cxb" -o "docs/gallery/${s}_below.png" --size 640x400 --camera "$1" --target "$2" -q
  fi
done
# Demonstration scenes (assets/demo/: not canonical, no tests).
for json in assets/demo/*.json; do
  s=$(basename "$json" .json)
  $B/bake/caustix-bake "$json" -o "$T/$s.cxb" -q
  $B/runtime/caustix-render "$T/$s.cxb" -o "docs/gallery/$s.png" --size 640x400 -q
done
# glTF files opened in one step (no bake command: caustix-render bakes them
# into a cache); neither has lights, so both show the default rig.
for gltf in assets/gltf/materials.gltf assets/gltf/textured.gltf; do
  s=$(basename "$gltf" .gltf)
  $B/runtime/caustix-render "$gltf" -o "docs/gallery/${s}_gltf.png" --size 640x400 --cache "$T/cache" -q
done
