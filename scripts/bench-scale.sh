#!/usr/bin/env bash
# What caustics cost as a scene grows (docs/runtime-speed.md, "As the scene
# grows"): an 8 x 8 m pool under moving water (floor, walls and deck as in
# the default scene, twice its size) with N objects on its floor (spheres
# and boxes in turn, on a grid) and L suns, N in RECEIVERS, L in LIGHTS.
# Per scene, at the balanced preset and 640 x 480, in one run:
#   - ms per frame with the level maps and without caustics (--method none),
#     and their ratio;
#   - the engine's GL calls, draws and dispatches per steady frame (the
#     application's draws it makes through Engine::draw_object included),
#     and those the water's caustics add (with less without caustics);
#   - the engine's GPU memory at 1280 x 800, all of it and the light
#     side's (what CausticsOptions::memory_budget holds), with the
#     caustics maps' finest texel and the budget's coarsening;
#   - the fragment- and compute-shader invocations of a frame (the
#     pipeline statistics of caustix-bench frames --passes, summed over the
#     passes).
#
#   scripts/bench-scale.sh [OUT_DIR]      (default docs/results)
#
# Writes OUT_DIR/scale_<renderer>.csv and, with matplotlib,
# OUT_DIR/scale.png (scripts/plot_scale.py). Needs the full build (build/)
# configured with -DCAUSTIX_COUNT_GL_CALLS=ON (as scripts/test.sh does).
# Environment: FRAMES (measured, median; default 3), WARMUP (default 2),
# RECEIVERS (default "1 4 16 64"), LIGHTS (default "1 2 4"; every N is
# measured with one light, N = 16 also with each L), RENDERER (a label;
# default llvmpipe), BUILD (the build folder whose binaries run; default
# build), ARGS (more options for every caustix-bench frames run, e.g.
# "--map-batching always" to draw the level maps in batches on llvmpipe).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
export MESA_SHADER_CACHE_DISABLE=true
out=${1:-docs/results}
FRAMES=${FRAMES:-3}
WARMUP=${WARMUP:-2}
RECEIVERS=${RECEIVERS:-"1 4 16 64"}
LIGHTS=${LIGHTS:-"1 2 4"}
RENDERER=${RENDERER:-llvmpipe}
B=${BUILD:-build}
source scripts/require-gl-counts.sh
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
mkdir -p "$out"

# The pool with n objects and l suns.
pool() {  # n l path
  /usr/bin/python3 - "$@" <<'PY'
import json, math, os, sys
n, l, path = int(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
j = json.load(open("assets/scenes/default.json"))
mesh = lambda m: os.path.abspath(os.path.join("assets/scenes", m))
tex = lambda t: os.path.abspath(os.path.join("assets/scenes", t))
objects = []
for o in j["objects"]:
    if o["name"] not in ("floor", "walls", "deck"):
        continue
    o["mesh"] = mesh(o["mesh"])
    t = o.get("material", {}).get("albedo_texture")
    if t:
        t["file"] = tex(t["file"])
    s = o["transform"]["scale"]
    o["transform"]["scale"] = [2 * s[0], s[1], 2 * s[2]]
    objects.append(o)
# n objects on a k x k grid over the floor's inner 7 x 7 m.
k = math.ceil(math.sqrt(n))
pitch = 7.0 / k
size = min(0.5, 0.6 * pitch)  # a ball's diameter, a box's side
for i in range(n):
    x = -3.5 + pitch * (i % k + 0.5)
    z = -3.5 + pitch * (i // k + 0.5)
    if i % 2 == 0:
        objects.append({"name": f"ball{i}", "mesh": mesh("../meshes/sphere.obj"), "role": "receiver",
                        "material": {"albedo": [0.9, 0.45, 0.25]},
                        "transform": {"translate": [x, size / 2, z], "scale": size / 2}})
    else:
        objects.append({"name": f"block{i}", "mesh": mesh("../meshes/box.obj"), "role": "receiver",
                        "material": {"albedo": [0.3, 0.6, 0.35]},
                        "transform": {"translate": [x, size / 2, z], "rotate_deg": [0, 30, 0], "scale": size}})
j["objects"] = objects
j["name"] = f"scale_{n}x{l}"
j["comment"] = "scripts/bench-scale.sh: the default pool at 8 x 8 m with objects on its floor"
# l suns around the sky, 20-35 degrees from the zenith.
j["lights"] = []
for i in range(l):
    a = 2 * math.pi * i / l + 0.6
    tilt = math.tan(math.radians(20 + 15 * i / max(l - 1, 1)))
    j["lights"].append({"type": "directional", "name": f"sun{i}",
                        "direction": [tilt * math.cos(a), -1.0, tilt * math.sin(a)], "irradiance": 1.0 / l})
j["water"]["grid"]["extent"] = [-4, -4, 4, 4]
j["water"]["grid"]["cells"] = [256, 256]
j["camera"] = {"position": [5.2, 8.8, 7.8], "target": [0, 0.7, 0], "fov_y_deg": 50}
json.dump(j, open(path, "w"), indent=1)
PY
}

cases=""
for n in $RECEIVERS; do cases="$cases $n:1"; done
for l in $LIGHTS; do [ "$l" = 1 ] || cases="$cases 16:$l"; done

csv=$out/scale_$RENDERER.csv
echo "receivers,lights,objects,ms,ms_without_caustics,ratio,gl_calls,draws,dispatches,draws_dispatches,gpu_mb_1280x800,fs_invocations,cs_invocations,renderer,light_side_mb_1280x800,texel_mm,coarsened,caustics_draws_dispatches" >"$csv"
field() { /usr/bin/python3 -c 'import csv,sys; r = next(csv.reader([sys.argv[1]])); k = int(sys.argv[2]); print(r[k] if k < len(r) else "")' "$1" "$2"; }
for c in $cases; do
  n=${c%%:*}
  l=${c##*:}
  pool "$n" "$l" "$T/scale.json"
  $B/bake/caustix-bake "$T/scale.json" -o "$T/scale.cxb" --preset balanced -q
  # shellcheck disable=SC2086 # ARGS is a list of options
  bench() { $B/tools/caustix-bench frames "$T/scale.cxb" ${ARGS:-} "$@"; }
  measured=(--frames "$FRAMES" --warmup "$WARMUP")
  # caustix-bench frames: label,scene,method,planes,cull,size,median_ms,min_ms,planes_drawn,volumes_drawn,
  # volumes_total,gpu_mb,gl_calls,gl_syncs,draws,dispatches,upload_bytes,renderer,light_side_mb,texel_mm,coarsened
  # (the last three absent from builds before texels by need)
  with=$(bench "${measured[@]}")
  without=$(bench "${measured[@]}" --method none)
  memory=$(bench --size 1280x800 --frames 1 --warmup 1)
  rm -f "$T/passes.csv"
  bench --frames 2 --warmup "$WARMUP" --passes "$T/passes.csv" >/dev/null  # the first measured frame's counts arrive during the second
  invocations=$(/usr/bin/python3 - "$T/passes.csv" <<'PY'
import csv, sys
rows = [r for r in csv.DictReader(open(sys.argv[1])) if not r["pass"].startswith("all ")]
fs = sum(int(r["fs_invocations"] or 0) for r in rows)
cs = sum(int(r["cs_invocations"] or 0) for r in rows)
print(f"{fs},{cs}")
PY
)
  ms=$(field "$with" 6)
  ms0=$(field "$without" 6)
  draws=$(field "$with" 14)
  dispatches=$(field "$with" 15)
  objects=$((n + 3))
  ratio=$(/usr/bin/python3 -c "print(f'{$ms / $ms0:.2f}')")
  own=$((draws + dispatches - $(field "$without" 14) - $(field "$without" 15)))
  echo "$n,$l,$objects,$ms,$ms0,$ratio,$(field "$with" 12),$draws,$dispatches,$((draws + dispatches)),$(field "$memory" 11),$invocations,\"$(field "$with" 17)\",$(field "$memory" 18),$(field "$memory" 19),$(field "$memory" 20),$own" >>"$csv"
  echo "scale: $n receivers x $l lights: $ms ms ($ratio x without caustics), $((draws + dispatches)) draws + dispatches ($own the water's caustics')"
done
echo "wrote $csv"
if /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then /usr/bin/python3 scripts/plot_scale.py "$out"; fi
