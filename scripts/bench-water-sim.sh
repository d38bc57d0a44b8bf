#!/usr/bin/env bash
# Regenerates docs/results/water_sim_<renderer>.csv, water_sim_cost.png and
# water_sim_ripples.png (docs/water-simulation.md): the interactive water's
# cost per 60 Hz frame over grid sizes and its parts on thesis_sphere
# (caustix-bench water-sim), and the picture of two ripples 1.5 s after
# they were dropped. Needs a built tree; installs python3-matplotlib if
# missing. About a minute on 2 cores with llvmpipe. RENDERER_TAG names the
# CSV (default llvmpipe; e.g. h100 on a GPU machine).
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
TAG=${RENDERER_TAG:-llvmpipe}
$B/bake/caustix-bake assets/scenes/thesis_sphere.json -o "$T/ts.cxb" -q
$B/tools/caustix-bench water-sim "$T/ts.cxb" --frames 20 --csv "docs/results/water_sim_$TAG.csv"
/usr/bin/python3 scripts/plot_water_sim.py "docs/results/water_sim_$TAG.csv" docs/results/water_sim_cost.png
R="--ripple 1,1,0.15,0.03 --ripple -1,0.5,0.1,0.02 --simulate 1.5"
$B/runtime/caustix-render "$T/ts.cxb" -o "$T/beauty.png" --size 640x400 $R -q
$B/runtime/caustix-render "$T/ts.cxb" -o "$T/irr.exr" --size 400x400 --irradiance floor --pixel-samples 2 $R -q
oiiotool "$T/irr.exr" --mulc 0.6 --colorconvert linear sRGB -o "$T/irr.png"
oiiotool "$T/beauty.png" "$T/irr.png" --resize 400x400 --mosaic 2x1 -o docs/results/water_sim_ripples.png
