#!/usr/bin/env bash
# What a frame of the runtime costs the application (
# docs/runtime-speed.md, "What a frame costs"): per canonical scene at the
# balanced preset, 640 x 480, the engine's GL calls, draws, dispatches and
# GPU -> CPU synchronisations per steady frame and the ms per frame, with
# the waves moving, with everything still (time paused), without caustics,
# and with the light turning; the GL calls against the plane count; the
# engine's GPU memory per effect at 1280 x 800 (caustix-render -v); the
# GPU time per pass (caustix-bench frames --passes).
#
#   scripts/bench-frame-cost.sh [OUT_DIR]      (default docs/results)
#
# Needs the full build (build/) configured with -DCAUSTIX_COUNT_GL_CALLS=ON
# (as scripts/test.sh configures it): without the counter there are no
# GL calls to report. With OLD=DIR holding caustix-bake,
# caustix-bench and caustix-render built from an earlier commit, every
# timed row runs with those too, side by side in the same run (same
# machine, alternating), labelled "before"; their .cxb files are baked by
# the old baker. Environment: FRAMES (measured, median; default 3), WARMUP
# (default 2), SCENES.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
export MESA_SHADER_CACHE_DISABLE=true
out=${1:-docs/results}
FRAMES=${FRAMES:-3}
WARMUP=${WARMUP:-2}
SCENES=${SCENES:-"thesis_teapot glass_ball mirror_ring fog_ball dispersive_pool flat_pool wavy_pool glass_teapot default"}
# Memory of every canonical scene (and the dispersive pool).
MEMORY_SCENES=${MEMORY_SCENES:-"$(ls assets/scenes | sed 's/\.json$//' | tr '\n' ' ') dispersive_pool"}
B=build
source scripts/require-gl-counts.sh
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
mkdir -p "$out"

# The dispersive pool: wavy_pool's water with dispersion 3 and its sine moving.
/usr/bin/python3 - "$T/dispersive_pool.json" <<'PY'
import json, os, sys
j = json.load(open("assets/scenes/wavy_pool.json"))
for o in j["objects"]:
    o["mesh"] = os.path.abspath(os.path.join("assets/scenes", o["mesh"]))
j["water"]["dispersion"] = 3.0
j["water"]["waves"][0]["speed"] = 0.5
json.dump(j, open(sys.argv[1], "w"))
PY
src() { [ "$1" = dispersive_pool ] && echo "$T/dispersive_pool.json" || echo "assets/scenes/$1.json"; }
for s in $MEMORY_SCENES; do $B/bake/caustix-bake "$(src "$s")" -o "$T/$s.cxb" --preset balanced -q; done
for s in $SCENES; do
  if [ -n "${OLD:-}" ]; then "$OLD/caustix-bake" "$(src "$s")" -o "$T/${s}_old.cxb" --preset balanced -q; fi
done

# 1. Frames: counts and ms, new (and old) side by side.
frames=$out/frame_cost_llvmpipe.csv
echo "build,scene,case,method,planes,median_ms,gl_calls,gl_syncs,draws,dispatches,upload_bytes,gpu_mb,renderer" >"$frames"
row() {  # build scene case args...
  local build=$1 s=$2 case=$3 bench cxb line
  shift 3
  if [ "$build" = before ]; then bench="$OLD/caustix-bench"; cxb="$T/${s}_old.cxb"; else bench=$B/tools/caustix-bench; cxb="$T/$s.cxb"; fi
  line=$("$bench" frames "$cxb" --frames "$FRAMES" --warmup "$WARMUP" "$@")
  /usr/bin/python3 - "$build" "$s" "$case" "$line" >>"$frames" <<'PY'
import csv, sys
build, s, case, line = sys.argv[1:]
f = next(csv.reader([line]))
# label,scene,method,planes,cull,size,median_ms,min_ms,planes_drawn,primitives_drawn,volumes_total,gpu_mb[,gl_calls,gl_syncs,draws,dispatches,upload_bytes],renderer
counts = f[12:17] if len(f) > 13 else [""] * 5
print(",".join([build, s, case, f[2], f[3], f[6]] + counts + [f[11], '"' + f[-1] + '"']))
PY
  tail -1 "$frames"
}
both() {  # scene case args...
  row after "$@"
  [ -n "${OLD:-}" ] || return 0
  local s=$1 case=$2 args=()
  shift 2
  # The old bench has no --still; without water its frames are still anyway.
  for a in "$@"; do [ "$a" = --still ] || args+=("$a"); done
  if [ ${#args[@]} -lt $# ] && grep -q '"water"' "$(src "$s")"; then return 0; fi
  row before "$s" "$case" ${args[@]+"${args[@]}"}
}
for s in $SCENES; do
  both "$s" animated
  both "$s" still --still
  both "$s" "no caustics (still)" --still --method none
  both "$s" "light turning" --move-light
done
for m in levelmap uniform volumetric; do
  for n in 8 101; do both thesis_teapot "planes $n" --method "$m" --planes "$n"; done
done

# 2. Memory per effect at 1280 x 800 (caustix-render's default 2 x 2 supersampling).
memory=$out/frame_cost_memory_llvmpipe.csv
echo "scene,size,total_mb,level_maps,shadow_maps,glass,caustic_maps,media,water,views,meshes,other" >"$memory"
for s in $MEMORY_SCENES; do
  $B/runtime/caustix-render "$T/$s.cxb" -o "$T/$s.png" --size 1280x800 -v | /usr/bin/python3 -c '
import re, sys
s = sys.argv[1]
for line in sys.stdin:
    if line.startswith("engine GPU memory"):
        v = [float(x) for x in re.findall(r"(\d+\.\d+)", line)]
        print(",".join([s, "1280x800"] + ["%.2f" % x for x in v]))
' "$s" | tee -a "$memory"
done

# 3. GPU time per pass (timer queries; llvmpipe's are CPU time, but the split holds).
passes=$out/frame_cost_passes_llvmpipe.csv
rm -f "$passes"
for s in thesis_teapot glass_ball mirror_ring fog_ball dispersive_pool; do
  $B/tools/caustix-bench frames "$T/$s.cxb" --frames "$FRAMES" --warmup "$WARMUP" --label "$s" --passes "$passes" >/dev/null
done
echo "bench-frame-cost: wrote $frames, $memory and $passes"
/usr/bin/python3 scripts/plot_frame_cost.py "$out"
