#!/usr/bin/env bash
# Regenerates the speed/accuracy sweeps of docs/tradeoff.md: a reference
# image per canonical scene (caustix-reference, cached in build/tradeoff/),
# then caustix-bench tradeoff (every knob from the 'balanced' preset, then
# the presets) -> docs/results/tradeoff_<scene>.csv and .png. Needs a built
# tree (scripts/test.sh or scripts/run-default.sh); installs
# python3-matplotlib if missing. About 60 minutes on 2 cores with llvmpipe.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get install -y -qq --no-install-recommends python3-matplotlib >/dev/null
fi
cmake --build build --target caustix-bench caustix-reference
mkdir -p build/tradeoff docs/results

# scene, receiver, region, image size, photons: 1.5-2.5 cm pixels, reference
# noise 1.4 % per pixel (glass_ball: 1.6 cm pixels, 2 %).
# An optional sixth argument names a second sweep of the same scene
# (tradeoff_<scene>_<tag>.csv) and the knobs after it limit it.
run() {
  local scene=$1 receiver=$2 region=$3 size=$4 photons=$5 tag=${6:+_$6}
  local ref=build/tradeoff/${scene}${tag}_ref.exr
  if [ ! -f "$ref" ]; then
    ./build/tools/caustix-reference "assets/scenes/$scene.json" --irradiance "$receiver" --region "$region" \
      --size "$size" --photons "$photons" -o "$ref"
  fi
  ./build/tools/caustix-bench tradeoff "assets/scenes/$scene.json" --reference "$ref" \
    --csv "docs/results/tradeoff_$scene$tag.csv" "${@:7}"
}
run wavy_pool floor 0,-0.03125,4,0.03125 256x4 256000000
run thesis_teapot teapot -1.25,-0.8,1.35,0.8 104x64 128000000
run glass_ball floor -1,-1,1,1 128x128 32000000
# The focus: 1 mm pixels over +-5 cm, the focal columns
# (focus_1cm, focus_2cm, peak_ratio) judge what the eye goes to first.
run glass_ball floor -0.05,-0.05,0.05,0.05 100x100 24000000 focus --knobs glass-size glass-focus-tent glass-turn ltt-resolution glass-method cmap-size cmap-focus presets
# Media (docs/volume.md): in-scatter references, the media's knobs.
# An optional fifth argument names a second sweep of the same scene and the
# knobs after it limit it.
run_media() {
  local scene=$1 region=$2 size=$3 photons=$4 tag=${5:+_$5}
  local ref=build/tradeoff/${scene}${tag}_inscatter_ref.exr
  if [ ! -f "$ref" ]; then
    ./build/tools/caustix-reference "assets/scenes/$scene.json" --inscatter --region "$region" \
      --size "$size" --photons "$photons" -o "$ref"
  fi
  ./build/tools/caustix-bench tradeoff "assets/scenes/$scene.json" --reference "$ref" --size 320x200 \
    --csv "docs/results/tradeoff_$scene$tag.csv" "${@:6}"
}
run_media fog_ball -1.5,0,1.5,2.5 120x100 4000000
# The focal line: 1 cm pixels over the ball's focus; peak_ratio
# is the brightest pixel's in-scatter against the reference's, peak_m how
# far apart the two lie.
run_media fog_ball -0.1,0.3,0.1,0.75 20x45 16000000 focus --knobs focus-grid volume-grid volume-photons volume-res view-step surface-refraction presets
run_media shafts_pool -1.5,0,1.5,2.2 120x88 2000000
/usr/bin/python3 scripts/plot_tradeoff.py docs/results wavy_pool thesis_teapot glass_ball fog_ball shafts_pool
