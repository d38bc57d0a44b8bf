#!/usr/bin/env bash
# The focus windows side by side in one run: caustix-bench
# frames with the window ("window") and without it ("none"), and OLD's
# binary ("old", an earlier build, when given), alternating in rounds, with
# the light still and turning every frame; per-pass GPU times too.
# METHOD=caustic-map (the default) measures the caustic maps' window
# (docs/caustic-maps.md; none: --cmap-no-focus), METHOD=tables the glass
# tables' (docs/glass-focus.md; none: --glass-no-focus; with FULL=1 also "full":
# --glass-focus-spectral full, a dispersive glass's windows at their own
# texels).
#
#   [METHOD=caustic-map|tables] [FULL=1] [BENCH=build/tools/caustix-bench]
#   [OLD=DIR/caustix-bench] [SIZE=640x480] [FRAMES=8] [WARMUP=3] [ROUNDS=3]
#   [SCENES="glass_ball glass_teapot ..."]
#   scripts/bench-caustic-map-focus.sh CXB_DIR OUT_DIR
#
# CXB_DIR holds the scenes baked with the defaults (caustix-bake
# assets/scenes/NAME.json -o CXB_DIR/NAME.cxb). Writes OUT_DIR/frames.csv
# (label: variant-light-round) and OUT_DIR/passes_VARIANT.csv. On a machine
# with only a GPU driver, BENCH and OLD may be CAUSTIX_PARTS=runtime builds.
set -euo pipefail
BENCH=${BENCH:-build/tools/caustix-bench}
SIZE=${SIZE:-640x480}
FRAMES=${FRAMES:-8}
WARMUP=${WARMUP:-3}
ROUNDS=${ROUNDS:-3}
METHOD=${METHOD:-caustic-map}
case $METHOD in
  caustic-map) method=(--glass-method caustic-map); no_focus=--cmap-no-focus
    SCENES=${SCENES:-glass_ball glass_teapot dispersive_ball mirror_ring} ;;
  tables) method=(); no_focus=--glass-no-focus
    SCENES=${SCENES:-glass_ball glass_teapot dispersive_ball} ;;
  *) echo "METHOD must be caustic-map or tables" >&2; exit 2 ;;
esac
CXB=$1
OUT=$2
mkdir -p "$OUT"
header=--header
for round in $(seq 1 "$ROUNDS"); do
  for scene in $SCENES; do
    for light in still turning; do
      move=()
      [ "$light" = turning ] && move=(--move-light)
      for variant in window none full old; do
        case $variant in
          window) bench=$BENCH; extra=() ;;
          none) bench=$BENCH; extra=("$no_focus") ;;
          full) [ "$METHOD" = tables ] && [ -n "${FULL:-}" ] || continue; bench=$BENCH; extra=(--glass-focus-spectral full) ;;
          old) [ -n "${OLD:-}" ] || continue; bench=$OLD; extra=() ;;
        esac
        "$bench" frames "$CXB/$scene.cxb" "${method[@]}" "${extra[@]}" "${move[@]}" --size "$SIZE" \
          --frames "$FRAMES" --warmup "$WARMUP" --label "$variant-$light-$round" $header \
          --passes "$OUT/passes_$variant.csv" >> "$OUT/frames.csv"
        header=
      done
    done
  done
done
