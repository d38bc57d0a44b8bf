#!/usr/bin/env bash
# Regenerates docs/results/dispersion.csv and the trade-off rows
# docs/results/tradeoff_dispersion.csv (docs/dispersion.md): the dispersive
# ball (assets/scenes/dispersive_ball.json) through image-space caustic maps
# at 1..32 traced wavelengths against the spectral caustix-reference (per
# photon wavelengths): relative L1 per colour channel, GPU ms of the photon
# and splat passes; then the monochromatic images at the F, d and C lines
# against monochromatic references; then the same passes on glass_ball (no
# dispersion) side by side. About 10 minutes on 2 cores with llvmpipe.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake --build build
B=build
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
R="-0.5,-0.5,0.5,0.5"
$B/bake/caustix-bake assets/scenes/dispersive_ball.json -o "$T/db.cxb" -q
$B/bake/caustix-bake assets/scenes/glass_ball.json -o "$T/gb.cxb" -q
$B/tools/caustix-reference assets/scenes/dispersive_ball.json --irradiance floor --region $R --size 200 --photons 16000000 \
  -o "$T/ref.exr" >/dev/null
OUT=docs/results/dispersion.csv
echo "scene,wavelengths,wavelength_nm,rel_l1_r,rel_l1_g,rel_l1_b,flux_ratio_g,photon_ms,splat_ms,renderer" > "$OUT"
# Relative L1 of one channel: both images' channel copied into all three,
# so that caustix-compare's luminance is that channel.
channel_l1() {  # image reference channel
  oiiotool "$1" --ch "$3,$3,$3" -o "$T/a.exr" && oiiotool "$2" --ch "$3,$3,$3" -o "$T/b.exr"
  $B/tools/caustix-compare --json "$T/a.exr" "$T/b.exr"
}
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
