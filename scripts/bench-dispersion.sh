#!/usr/bin/env bash
# Dispersion's measurements for docs/dispersion.md. Usage:
#   scripts/bench-dispersion.sh [glass|tables|water|view|all]   (default all)
# glass: docs/results/dispersion.csv and the trade-off rows
#   docs/results/tradeoff_dispersion.csv: the dispersive ball
#   (assets/scenes/dispersive_ball.json) through image-space caustic maps at
#   1..32 traced wavelengths against the spectral caustix-reference (per
#   photon wavelengths): relative L1 per colour channel, GPU ms of the photon
#   and splat passes; then the monochromatic images at the F, d and C lines
#   against monochromatic references; then the same passes on glass_ball (no
#   dispersion) side by side. About 10 minutes on 2 cores with llvmpipe.
# tables: docs/results/dispersion_tables.csv: the dispersive ball through its
#   light-transport tables, baked with --ltt-wavelengths 0, 2, 4 and 8 (bake
#   seconds, file bytes), at 1..16 traced wavelengths against the spectral
#   reference (relative L1 per channel) with ms per 640x480 frame; the F, d
#   and C lines against monochromatic references; glass_ball at 1 and 8
#   side by side; then the trade-off rows of the traced and the baked
#   wavelengths (docs/results/tradeoff_dispersion_tables.csv). About 15
#   minutes.
# water: docs/results/dispersion_water.csv: wavy_pool's water with
#   dispersion 3 over a 1.5 m pool, the level-map, volumetric and splat
#   methods at 1..16 wavelengths against the spectral reference (relative L1
#   per channel) and ms per 640x480 frame; the same pool without dispersion
#   at 8 (it traces one); shafts_pool's scattering water with dispersion 3,
#   ms per frame with the media at 1, 4 and 8 wavelengths; and
#   docs/results/dispersion_media.csv: its in-scatter image at 1, 2, 4 and 8
#   wavelengths against the spectral in-scatter reference (relative L1 per
#   channel). About 8 minutes.
# view: docs/results/dispersion_view.csv: the cost of the refracted views
#   per wavelength: ms per 640x480 frame of the dispersive ball (baked with
#   its tables at n_d only, so that its light traces one wavelength) seen
#   through the table view (n_d) and the nearby view (per wavelength) at 1..16
#   wavelengths, glass_ball's nearby view at 1 and 8; the dispersive pool
#   of the water part with the light passes off (method none: the water
#   view alone traces the wavelengths) at 1..16, and the pool without
#   dispersion at 1 and 8; pictures of the views' fringes
#   (docs/results/dispersive_{ball,water}_view_fringes.png). About 3 minutes.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build
B=build
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
PART=${1:-all}
case "$PART" in glass|tables|water|view|all) ;; *) echo "usage: $0 [glass|tables|water|view|all]" >&2; exit 2 ;; esac
# Relative L1 of one channel: both images' channel copied into all three,
# so that caustix-compare's luminance is that channel.
channel_l1() {  # image reference channel
  oiiotool "$1" --ch "$3,$3,$3" -o "$T/a.exr" && oiiotool "$2" --ch "$3,$3,$3" -o "$T/b.exr"
  $B/tools/caustix-compare --json "$T/a.exr" "$T/b.exr"
}
glass() {
  local R="-0.5,-0.5,0.5,0.5" OUT=docs/results/dispersion.csv
  # The ball's tables at n_d only: its light traces one wavelength, so the
  # nearby view is all that grows with the count.
  $B/bake/caustix-bake assets/scenes/dispersive_ball.json -o "$T/db0.cxb" -q --ltt-wavelengths 0
  $B/bake/caustix-bake assets/scenes/dispersive_ball.json -o "$T/db.cxb" -q
  $B/bake/caustix-bake assets/scenes/glass_ball.json -o "$T/gb.cxb" -q
  $B/tools/caustix-reference assets/scenes/dispersive_ball.json --irradiance floor --region $R --size 200 --photons 16000000 \
    -o "$T/ref.exr" >/dev/null
  echo "scene,wavelengths,wavelength_nm,rel_l1_r,rel_l1_g,rel_l1_b,flux_ratio_g,photon_ms,splat_ms,renderer" > "$OUT"
  row() {  # scene cxb reference label-wavelengths label-nm [render options]
    local s=$1 cxb=$2 ref=$3 n=$4 nm=$5; shift 5
    local log
    log=$($B/runtime/caustix-render "$cxb" --irradiance floor --region $R --size 200 --glass-method caustic-map -o "$T/img.exr" -v "$@")
    /usr/bin/python3 - "$s" "$n" "$nm" "$(channel_l1 "$T/img.exr" "$ref" R)" "$(channel_l1 "$T/img.exr" "$ref" G)" \
      "$(channel_l1 "$T/img.exr" "$ref" B)" "$log" >> "$OUT" <<'PY'
import json, re, sys
s, n, nm, r, g, b, log = sys.argv[1:]
r, g, b = (json.loads(x) for x in (r, g, b))
m = re.search(r"photons ([\d.]+) ms, splat ([\d.]+) ms", log)
ren = re.search(r"renderer: (.*)", log).group(1)
print(f'{s},{n},{nm},{r["rel_l1"]:.5f},{g["rel_l1"]:.5f},{b["rel_l1"]:.5f},{g["flux_ratio"]:.5f},{m.group(1)},{m.group(2)},"{ren}"')
PY
  }
  for n in 1 2 4 8 16 32; do row dispersive_ball "$T/db.cxb" "$T/ref.exr" $n rgb --wavelengths $n; done
  for nm in 486.13 587.56 656.27; do
    $B/tools/caustix-reference assets/scenes/dispersive_ball.json --irradiance floor --region $R --size 200 --photons 8000000 \
      --wavelength $nm -o "$T/ref_$nm.exr" >/dev/null
    row dispersive_ball "$T/db.cxb" "$T/ref_$nm.exr" 1 $nm --wavelength $nm
  done
  # No dispersion: one wavelength whatever --wavelengths says (the cost of before).
  $B/tools/caustix-reference assets/scenes/glass_ball.json --irradiance floor --region $R --size 200 --photons 8000000 \
    -o "$T/gref.exr" >/dev/null
  for n in 1 8; do row glass_ball "$T/gb.cxb" "$T/gref.exr" $n rgb --wavelengths $n; done
  $B/tools/caustix-bench tradeoff assets/scenes/dispersive_ball.json --reference "$T/ref.exr" --pixel-samples 4 \
    --knobs wavelengths --csv docs/results/tradeoff_dispersion.csv >/dev/null
}

# A scene derived from a canonical one: JSON edits applied, mesh paths made
# absolute.
derive() {  # canonical-name output python-edits
  /usr/bin/python3 - "$1" "$2" "$3" <<'PY'
import json, os, sys
name, out, edit = sys.argv[1:]
j = json.load(open(f"assets/scenes/{name}.json"))
for o in j["objects"]:
    o["mesh"] = os.path.abspath(os.path.join("assets/scenes", o["mesh"]))
exec(edit)
json.dump(j, open(out, "w"))
PY
}

tables() {
  local R="-0.5,-0.5,0.5,0.5" OUT=docs/results/dispersion_tables.csv
  echo "scene,ltt_wavelengths,bake_s,cxb_bytes,wavelengths,wavelength_nm,rel_l1_r,rel_l1_g,rel_l1_b,flux_ratio_g,frame_ms,renderer" > "$OUT"
  for k in 0 2 4 8; do
    /usr/bin/python3 - "$k" "$T" <<'PY' > "$T/bake_$k.txt"
import subprocess, sys, time
k, t = sys.argv[1:]
start = time.monotonic()
subprocess.run(["build/bake/caustix-bake", "assets/scenes/dispersive_ball.json", "-o", f"{t}/db{k}.cxb", "-q",
                "--ltt-wavelengths", k], check=True)
print(f"{time.monotonic() - start:.2f}")
PY
  done
  $B/bake/caustix-bake assets/scenes/glass_ball.json -o "$T/gb.cxb" -q
  $B/tools/caustix-reference assets/scenes/dispersive_ball.json --irradiance floor --region $R --size 200 --photons 16000000 \
    -o "$T/ref.exr" >/dev/null
  trow() {  # scene ltt-wavelengths cxb reference wavelengths nm [render options]
    local s=$1 k=$2 cxb=$3 ref=$4 n=$5 nm=$6; shift 6
    $B/runtime/caustix-render "$cxb" --irradiance floor --region $R --size 200 -o "$T/img.exr" "$@" >/dev/null
    local line
    line=$($B/tools/caustix-bench frames "$cxb" --wavelengths "$n" --warmup 1 --frames 3)
    /usr/bin/python3 - "$s" "$k" "$(cat "$T/bake_$k.txt" 2>/dev/null || echo)" "$(stat -c %s "$cxb")" "$n" "$nm" \
      "$(channel_l1 "$T/img.exr" "$ref" R)" "$(channel_l1 "$T/img.exr" "$ref" G)" "$(channel_l1 "$T/img.exr" "$ref" B)" \
      "$line" >> "$OUT" <<'PY'
import csv, json, sys
s, k, bake, size, n, nm, r, g, b, line = sys.argv[1:]
r, g, b = (json.loads(x) for x in (r, g, b))
f = next(csv.reader([line]))
print(f'{s},{k},{bake},{size},{n},{nm},{r["rel_l1"]:.5f},{g["rel_l1"]:.5f},{b["rel_l1"]:.5f},{g["flux_ratio"]:.5f},{f[6]},"{f[-1]}"')
PY
  }
  for n in 1 2 4 8 16; do trow dispersive_ball 2 "$T/db2.cxb" "$T/ref.exr" $n rgb --wavelengths $n; done
  for k in 0 4 8; do trow dispersive_ball $k "$T/db$k.cxb" "$T/ref.exr" 8 rgb --wavelengths 8; done
  for nm in 486.13 587.56 656.27; do
    $B/tools/caustix-reference assets/scenes/dispersive_ball.json --irradiance floor --region $R --size 200 --photons 8000000 \
      --wavelength $nm -o "$T/ref_$nm.exr" >/dev/null
    for k in 2 8; do trow dispersive_ball $k "$T/db$k.cxb" "$T/ref_$nm.exr" 1 $nm --wavelength $nm; done
  done
  $B/tools/caustix-reference assets/scenes/glass_ball.json --irradiance floor --region $R --size 200 --photons 8000000 \
    -o "$T/gref.exr" >/dev/null
  for n in 1 8; do trow glass_ball none "$T/gb.cxb" "$T/gref.exr" $n rgb --wavelengths $n; done
  $B/tools/caustix-bench tradeoff assets/scenes/dispersive_ball.json --reference "$T/ref.exr" --pixel-samples 4 \
    --knobs table-wavelengths,ltt-wavelengths --csv docs/results/tradeoff_dispersion_tables.csv >/dev/null
}

# wavy_pool's water over a 1.5 m pool (96 x 4 cells, wavy_pool's spacing):
# $T/pool.json with dispersion 3, $T/plain.json without.
pools() {
  local grid='j["water"]["grid"] = {"cells": [96, 4], "extent": [-0.25, -0.75, 1.25, 0.75]}'
  derive wavy_pool "$T/pool.json" "j[\"water\"][\"dispersion\"] = 3.0; $grid"
  derive wavy_pool "$T/plain.json" "$grid"
}

water() {
  local R="0,-0.5,1,0.5" OUT=docs/results/dispersion_water.csv
  pools
  derive shafts_pool "$T/shafts.json" 'j["water"]["dispersion"] = 3.0'
  for s in pool plain shafts; do $B/bake/caustix-bake "$T/$s.json" -o "$T/$s.cxb" -q; done
  $B/tools/caustix-reference "$T/pool.json" --irradiance floor --region $R --size 200 --photons 16000000 -o "$T/wref.exr" >/dev/null
  echo "scene,method,wavelengths,rel_l1_r,rel_l1_g,rel_l1_b,flux_ratio_g,frame_ms,renderer" > "$OUT"
  wrow() {  # scene cxb method wavelengths [reference]
    local s=$1 cxb=$2 m=$3 n=$4 ref=${5:-} r="" g="" b="" flux="" line
    if [ -n "$ref" ]; then
      $B/runtime/caustix-render "$cxb" --irradiance floor --region $R --size 200 --method "$m" --wavelengths "$n" -o "$T/img.exr" >/dev/null
      r=$(channel_l1 "$T/img.exr" "$ref" R); g=$(channel_l1 "$T/img.exr" "$ref" G); b=$(channel_l1 "$T/img.exr" "$ref" B)
    fi
    line=$($B/tools/caustix-bench frames "$cxb" --method "$m" --wavelengths "$n" --warmup 1 --frames 3)
    /usr/bin/python3 - "$s" "$m" "$n" "$r" "$g" "$b" "$line" >> "$OUT" <<'PY'
import csv, json, sys
s, m, n, r, g, b, line = sys.argv[1:]
f = next(csv.reader([line]))
if r:
    r, g, b = (json.loads(x) for x in (r, g, b))
    err = f'{r["rel_l1"]:.5f},{g["rel_l1"]:.5f},{b["rel_l1"]:.5f},{g["flux_ratio"]:.5f}'
else:
    err = ",,,"
print(f'{s},{m},{n},{err},{f[6]},"{f[-1]}"')
PY
  }
  for m in levelmap volumetric splat; do
    for n in 1 2 4 8 16; do wrow dispersive_pool "$T/pool.cxb" $m $n "$T/wref.exr"; done
  done
  for n in 1 8; do wrow plain_pool "$T/plain.cxb" levelmap $n; done
  for n in 1 4 8; do wrow dispersive_shafts_pool "$T/shafts.cxb" levelmap $n; done
  # The media's in-scatter against the spectral reference (as bench-tradeoff.sh's shafts_pool row).
  local IR="-1.5,0,1.5,2.2" MOUT=docs/results/dispersion_media.csv
  $B/tools/caustix-reference "$T/shafts.json" --inscatter --region $IR --size 120x88 --photons 4000000 -o "$T/iref.exr" >/dev/null
  echo "scene,wavelengths,rel_l1_r,rel_l1_g,rel_l1_b,flux_ratio_g" > "$MOUT"
  for n in 1 2 4 8; do
    $B/runtime/caustix-render "$T/shafts.cxb" --inscatter --region $IR --size 120x88 --wavelengths $n -o "$T/img.exr" >/dev/null
    /usr/bin/python3 - "$n" "$(channel_l1 "$T/img.exr" "$T/iref.exr" R)" "$(channel_l1 "$T/img.exr" "$T/iref.exr" G)" \
      "$(channel_l1 "$T/img.exr" "$T/iref.exr" B)" >> "$MOUT" <<'PY'
import json, sys
n, r, g, b = sys.argv[1:]
r, g, b = (json.loads(x) for x in (r, g, b))
print(f'dispersive_shafts_pool,{n},{r["rel_l1"]:.5f},{g["rel_l1"]:.5f},{b["rel_l1"]:.5f},{g["flux_ratio"]:.5f}')
PY
  done
}

view() {
  local OUT=docs/results/dispersion_view.csv
  # The ball's tables at n_d only: its light traces one wavelength, so the
  # nearby view is all that grows with the count.
  $B/bake/caustix-bake assets/scenes/dispersive_ball.json -o "$T/db0.cxb" -q --ltt-wavelengths 0
  $B/bake/caustix-bake assets/scenes/dispersive_ball.json -o "$T/db.cxb" -q
  $B/bake/caustix-bake assets/scenes/glass_ball.json -o "$T/gb.cxb" -q
  pools
  for s in pool plain; do $B/bake/caustix-bake "$T/$s.json" -o "$T/$s.cxb" -q; done
  echo "scene,view,method,wavelengths,frame_ms,renderer" > "$OUT"
  vrow() {  # scene cxb view method wavelengths
    local line
    line=$($B/tools/caustix-bench frames "$2" --glass-view "$3" --method "$4" --wavelengths "$5" --warmup 2 --frames 9)
    /usr/bin/python3 - "$1" "$3" "$4" "$5" "$line" >> "$OUT" <<'PY'
import csv, sys
s, v, m, n, line = sys.argv[1:]
f = next(csv.reader([line]))
print(f'{s},{v},{m},{n},{f[6]},"{f[-1]}"')
PY
  }
  for n in 1 4 8 16; do
    for v in table nearby; do vrow dispersive_ball_nd_tables "$T/db0.cxb" $v levelmap $n; done
  done
  for n in 1 8; do vrow glass_ball "$T/gb.cxb" nearby levelmap $n; done
  for n in 1 4 8 16; do vrow dispersive_pool "$T/pool.cxb" table none $n; done
  for n in 1 8; do vrow plain_pool "$T/plain.cxb" table none $n; done
  # Pictures, 1 wavelength above 8, each crop magnified: the inverted
  # horizon seen through the dispersive ball (nearby view), and wavy_pool's
  # floor through its water at dispersion 3 (method none: no caustics, so
  # the colour is the view's alone).
  derive wavy_pool "$T/wavy.json" 'j["water"]["dispersion"] = 3.0'
  $B/bake/caustix-bake "$T/wavy.json" -o "$T/wavy.cxb" -q
  for n in 1 8; do
    $B/runtime/caustix-render "$T/db.cxb" --glass-view nearby --camera 0.9,1.6,1.3 --target 0,0.6,0 --wavelengths $n \
      -o "$T/ball$n.png" >/dev/null
    $B/runtime/caustix-render "$T/wavy.cxb" --method none --wavelengths $n -o "$T/wavy$n.png" >/dev/null
  done
  oiiotool "$T/ball1.png" --cut 180x60+230+250 --resize 720x240 "$T/ball8.png" --cut 180x60+230+250 --resize 720x240 \
    --mosaic 1x2 -o docs/results/dispersive_ball_view_fringes.png
  oiiotool "$T/wavy1.png" --cut 200x100+0+200 --resize 600x300 "$T/wavy8.png" --cut 200x100+0+200 --resize 600x300 \
    --mosaic 1x2 -o docs/results/dispersive_water_view_fringes.png
}

case "$PART" in
  glass) glass ;;
  tables) tables ;;
  water) water ;;
  view) view ;;
  all) glass; tables; water; view ;;
esac
