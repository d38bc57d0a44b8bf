#!/usr/bin/env bash
# Every receiver lit from every light (docs/embedding.md,
# "Deferred and multi-light renderers"): the per-pair forward path
# (Engine::bind() and a draw per (receiver, light)) against the deferred
# pass over Engine::bind_all() (one full-screen draw), same G-buffer, same
# run; and update()'s cost with the water moving before and after the
# table exists. Scenes: canonical ones with lights added (a sun, a point
# light, a spot light), so that every scene has 3 lights.
#
#   scripts/bench-receivers.sh [OUT_DIR]      (default docs/results)
#
# Writes OUT_DIR/receivers_<renderer>.csv (llvmpipe, or gpu when
# RENDERER=gpu). Environment: FRAMES (default 5), WARMUP (default 2),
# SIZE (default 640x480), BENCH (default build/tools/caustix-bench),
# BAKED (a folder for the .cxb files: baked there unless an earlier run
# left them; a machine without the baker runs on those).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
export MESA_SHADER_CACHE_DISABLE=true
out=${1:-docs/results}
FRAMES=${FRAMES:-5}
WARMUP=${WARMUP:-2}
SIZE=${SIZE:-640x480}
BENCH=${BENCH:-build/tools/caustix-bench}
RENDERER=${RENDERER:-llvmpipe}
SCENES="wavy_pool thesis_teapot glass_ball mirror_ring default"
mkdir -p "$out"
BAKED=${BAKED:-$(mktemp -d)}
mkdir -p "$BAKED"
if [[ ! -f "$BAKED/default.cxb" ]]; then
  for s in $SCENES; do
    /usr/bin/python3 - "$s" "$BAKED/$s.json" <<'PY'
import json, os, sys
name, path = sys.argv[1], sys.argv[2]
j = json.load(open(f"assets/scenes/{name}.json"))
for o in j["objects"]:
    o["mesh"] = os.path.abspath(os.path.join("assets/scenes", o["mesh"]))
    t = o.get("material", {}).get("albedo_texture")
    if isinstance(t, str):
        o["material"]["albedo_texture"] = os.path.abspath(os.path.join("assets/scenes", t))
    elif isinstance(t, dict):
        t["file"] = os.path.abspath(os.path.join("assets/scenes", t["file"]))
extra = [
    {"type": "directional", "name": "second_sun", "direction": [-0.3, -1.0, 0.2], "irradiance": 0.5, "color": [0.4, 0.7, 1.0]},
    {"type": "point", "name": "lamp", "position": [1.0, 4.0, 0.5], "intensity": 6.0, "color": [1.0, 0.6, 0.3]},
    {"type": "spot", "name": "spot", "position": [-1.0, 3.0, 0.5], "direction": [0.3, -1.0, -0.2], "intensity": 3.0,
     "inner_cone_deg": 20.0, "outer_cone_deg": 35.0},
]
j["lights"] = (j["lights"] + extra)[:3]
json.dump(j, open(path, "w"))
PY
    build/bake/caustix-bake "$BAKED/$s.json" -o "$BAKED/$s.cxb" -q
  done
fi
csv="$out/receivers_$RENDERER.csv"
first=1
: >"$csv"
for s in $SCENES; do
  args=(receivers "$BAKED/$s.cxb" --size "$SIZE" --frames "$FRAMES" --warmup "$WARMUP" --label "$s")
  [[ $first == 1 ]] && args+=(--header)
  first=0
  "$BENCH" "${args[@]}" | tee -a "$csv"
done
