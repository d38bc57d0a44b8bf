#!/usr/bin/env bash
# Milliseconds per frame of the runtime, per canonical scene, bake preset and
# caustics method, plus re-derived level maps (a light turning every frame)
# and each water-surface effect: the tables of docs/runtime-speed.md. Runs
# wherever caustix-bench runs: Mesa llvmpipe here, a GPU through headless EGL
# (the same binary; a CAUSTIX_PARTS=runtime build needs only the GPU driver).
#
#   scripts/bench-runtime.sh BENCH CXB_DIR OUT_DIR
#
# BENCH: a caustix-bench binary. CXB_DIR: SCENE_PRESET.cxb files, as
# `scripts/bench-runtime.sh --bake CXB_DIR` writes them with the full build
# (every scene of assets/scenes at fast, balanced and accurate). OUT_DIR gets
# frames.csv and water.csv. Environment: FRAMES (measured, median reported;
# default 10), WARMUP (default 3), SIZES (default "640x480"), SCENES, PRESETS,
# METHODS to narrow the matrix.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
export MESA_SHADER_CACHE_DISABLE=true
SCENES=${SCENES:-"flat_pool wavy_pool thesis_sphere thesis_teapot thesis_organic glass_ball glass_teapot default"}
PRESETS=${PRESETS:-"fast balanced accurate"}

if [ "${1:-}" = "--bake" ]; then
  out=$2
  mkdir -p "$out"
  for s in $SCENES; do
    for p in $PRESETS; do
      "$here/build/bake/caustix-bake" "$here/assets/scenes/$s.json" -o "$out/${s}_$p.cxb" --preset "$p" -q
    done
  done
  exit 0
fi

bench=$1
cxb=$2
out=$3
FRAMES=${FRAMES:-10}
WARMUP=${WARMUP:-3}
SIZES=${SIZES:-640x480}
METHODS=${METHODS:-"levelmap uniform volumetric splat none"}
mkdir -p "$out"
frames_csv=$out/frames.csv
"$bench" frames --header "$cxb/flat_pool_fast.cxb" --frames 1 --warmup 0 | head -1 | sed 's/^label,/label,preset,/' >"$frames_csv"
row() {  # label preset args...
  local label=$1 preset=$2
  shift 2
  if line=$("$bench" frames "$@" --frames "$FRAMES" --warmup "$WARMUP" --label "$label" 2>/dev/null); then
    echo "${line/#$label,/$label,$preset,}" | tee -a "$frames_csv"
  else
    echo "$label,$preset,failed: $*" | tee -a "$frames_csv"
  fi
}
for size in $SIZES; do
  for s in $SCENES; do
    for p in $PRESETS; do
      f=$cxb/${s}_$p.cxb
      [ -f "$f" ] || continue
      for m in $METHODS; do
        row "$s" "$p" "$f" --method "$m" --size "$size"
      done
    done
    # Level maps re-derived on the GPU every frame (the light turns 2 degrees).
    [ -f "$cxb/${s}_balanced.cxb" ] && row "$s+move-light" balanced "$cxb/${s}_balanced.cxb" --method levelmap --size "$size" --move-light
  done
done
for size in $SIZES; do
  "$bench" water "$cxb/thesis_teapot_balanced.cxb" --size "$size" --frames "$FRAMES" --csv "$out/water_$size.csv" >/dev/null
done
echo "bench-runtime: wrote $frames_csv and $out/water_*.csv"
