#!/usr/bin/env bash
# Regenerates docs/results/caustic_maps.csv and caustic_maps.png
# (docs/caustic-maps.md): image-space caustic maps (timofy 2009) against the
# light-transport tables and caustix-reference on glass_ball, glass_teapot
# and mirror_ring -- the error of each (caustix-compare: relative L1, flux
# ratio, peak distance) and the GPU time of the caustic maps' passes, over
# the photon grid, the caustic map's size, the splat and the iterations;
# then ms per frame of the whole runtime with each glass method side by
# side (caustix-bench frames). Needs a built tree; installs
# python3-matplotlib if missing. About 25 minutes on 2 cores with llvmpipe.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get install -y -qq --no-install-recommends python3-matplotlib >/dev/null
fi
cmake --build build
B=build
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
OUT=docs/results/caustic_maps.csv
echo "scene,glass_method,knob,value,rel_l1,flux_ratio,peak_px,capture_ms,photon_ms,splat_ms,photons,landed,renderer" > "$OUT"
region() { case $1 in mirror_ring) echo "-0.6,-0.6,0.6,0.6" ;; *) echo "-1,-1,1,1" ;; esac; }
for s in glass_ball glass_teapot mirror_ring; do
  $B/bake/caustix-bake assets/scenes/$s.json -o "$T/$s.cxb" -q
  $B/tools/caustix-reference assets/scenes/$s.json --irradiance floor --region "$(region $s)" --size 200 \
    --photons 16000000 -o "$T/$s.ref.exr" >/dev/null
  run() {  # glass_method knob value [extra render options]
    local gm=$1 knob=$2 value=$3; shift 3
    local log
    log=$($B/runtime/caustix-render "$T/$s.cxb" --irradiance floor --region "$(region $s)" --size 200 \
      --glass-method "$gm" -o "$T/img.exr" -v "$@")
    local cmp
    cmp=$($B/tools/caustix-compare --json "$T/img.exr" "$T/$s.ref.exr")
    /usr/bin/python3 - "$s" "$gm" "$knob" "$value" "$cmp" "$log" >> "$OUT" <<'PY'
import json, re, sys
s, gm, knob, value, cmp, log = sys.argv[1:]
c = json.loads(cmp)
m = re.search(r"(\d+) photons, (\d+) landed.*capture ([\d.]+) ms, photons ([\d.]+) ms, splat ([\d.]+) ms", log)
r = re.search(r"renderer: (.*)", log).group(1)
cap, pho, spl, n, l = (m.group(3), m.group(4), m.group(5), m.group(1), m.group(2)) if m else ("", "", "", "", "")
print(f'{s},{gm},{knob},{value},{c["rel_l1"]:.5f},{c["flux_ratio"]:.5f},{c["peak_error_px"]:g},{cap},{pho},{spl},{n},{l},"{r}"')
PY
  }
  if [ $s != mirror_ring ]; then run table default 0; fi
  run caustic-map default 0
  for p in 64 128 256 1024 2048; do run caustic-map photons $p --cmap-photons $p; done
  for m in 256 1024 2048; do run caustic-map map_size $m --cmap-size $m; done
  for g in 0 0.5 2 4; do run caustic-map sigma $g --cmap-sigma $g; done
  run caustic-map two_pass 1 --cmap-two-pass
  for i in 1 2 4; do run caustic-map iterations $i --cmap-iterations $i; done
  # Adaptive caustic maps over a 1024^2 grid, 4 levels, at these budgets.
  for n in 4096 16384 65536 262144; do run caustic-map adaptive_budget $n --cmap-photons 1024 --cmap-adaptive 4 --cmap-budget $n; done
  if [ $s = mirror_ring ]; then
    for b in 1 4 8; do run caustic-map bounces $b --cmap-bounces $b; done
    for d in 0.5 1.0; do run caustic-map max_travel $d --cmap-max-travel $d; done
  else
    for e in 1 2 8; do run caustic-map exit_iterations $e --cmap-exit-iterations $e; done
    run caustic-map drop_tir 1 --cmap-drop-tir
    for e in 0.1 0.3; do run caustic-map edge_cos $e --cmap-edge-cos $e; done
    for d in 30 60; do run caustic-map max_deviation $d --cmap-max-deviation $d; done
  fi
done
# Whole frames (640x480, median of 10): each glass method side by side.
FR=docs/results/caustic_maps_frames.csv
$B/tools/caustix-bench frames "$T/glass_ball.cxb" --header --label glass_ball/table --glass-method table > "$FR"
for s in glass_ball glass_teapot; do
  [ $s = glass_ball ] || $B/tools/caustix-bench frames "$T/$s.cxb" --label $s/table --glass-method table >> "$FR"
  for p in 256 512 1024; do
    $B/tools/caustix-bench frames "$T/$s.cxb" --label "$s/caustic-map/$p" --glass-method caustic-map --cmap-photons $p >> "$FR"
  done
done
$B/tools/caustix-bench frames "$T/mirror_ring.cxb" --label mirror_ring/caustic-map/512 >> "$FR"
# The trade-off rows (docs/tradeoff.md): glass method, adaptive budget and
# VSM width on glass_ball; adaptive budget and the presets on mirror_ring.
$B/tools/caustix-bench tradeoff assets/scenes/glass_ball.json --reference "$T/glass_ball.ref.exr" --pixel-samples 4 \
  --knobs glass-method,cmap-budget,vsm-filter --csv docs/results/tradeoff_caustic_maps_glass_ball.csv >/dev/null
$B/tools/caustix-bench tradeoff assets/scenes/mirror_ring.json --reference "$T/mirror_ring.ref.exr" --pixel-samples 4 \
  --knobs cmap-budget,presets --csv docs/results/tradeoff_caustic_maps_mirror_ring.csv >/dev/null
/usr/bin/python3 scripts/plot_caustic_maps.py docs/results
