#!/usr/bin/env bash
# Tipprasert 2006 chapter 5 on our code (tables 5-1, 5-3, 5-5 and §5.1 memory):
# ms per frame against plane count for the level map (smart slicing),
# uniform slicing and the volumetric baseline, with our culling and in the
# thesis's plain mode (every volume through every plane); eq. 2-9
# differences between methods. Writes docs/results/chapter5_*.csv and plots.
# Needs a built tree; installs python3-matplotlib if missing.
# FRAMES (default 3) frames are measured after one warm-up frame.
set -euo pipefail
cd "$(dirname "$0")/.."
export MESA_SHADER_CACHE_DISABLE=true
FRAMES=${FRAMES:-3}
PLANES=${PLANES:-"3 8 16 32 64 100"}
SCENES=${SCENES:-"thesis_teapot thesis_sphere thesis_organic"}
cmake --build build --target caustix-bench caustix-bake >/dev/null
mkdir -p docs/results out
B=./build/tools/caustix-bench
timing=docs/results/chapter5_timing.csv
quality=docs/results/chapter5_quality.csv
$B frames --header out/none.cxb 2>/dev/null | head -1 >"$timing" || true
[ -s "$timing" ] || echo "label,scene,method,planes,cull,size,median_ms,min_ms,planes_drawn,primitives_drawn,volumes_total,gpu_mb,renderer" >"$timing"
echo "label,scene,planes,eq29_smart_vs_uniform,eq29_uniform_vs_volumetric,eq29_smart_vs_none" >"$quality"
for s in $SCENES; do
  ./build/bake/caustix-bake "assets/scenes/$s.json" -o "out/$s.cxb" -q
  for n in $PLANES; do
    for m in levelmap uniform volumetric; do
      $B frames "out/$s.cxb" --method "$m" --planes "$n" --frames "$FRAMES" --warmup 1 --label "$s" | tee -a "$timing"
    done
    for m in levelmap uniform; do
      $B frames "out/$s.cxb" --method "$m" --planes "$n" --frames "$FRAMES" --warmup 1 --no-cull --label "$s" | tee -a "$timing"
    done
    $B methods "out/$s.cxb" --planes "$n" --size 320x240 --label "$s" | tee -a "$quality"
  done
done
if ! /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get install -y -qq --no-install-recommends python3-matplotlib >/dev/null
fi
/usr/bin/python3 scripts/plot_caustics.py docs/results
