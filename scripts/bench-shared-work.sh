#!/usr/bin/env bash
# Shared work: twelve copies of one glass ball over a backdrop,
# exported as a DCC tool writes duplicated objects (scripts/twelve_balls.py:
# each ball its own glTF mesh, three colours of one glass, each turned),
# baked side by side in one run three ways: unshared (--no-share
# --ltt-rays cgal: every object its own mesh and tables, cast through CGAL,
# the old baker's bytes; BEFORE=/path/to/an/older/caustix-bake runs this
# row with that baker), with Embree alone (--no-share), and with sharing
# (the default), then rendered. For the 1 106-vertex ball and the 8 066-vertex
# one (assets/meshes/sphere_fine.obj). Per row: bake seconds and peak
# memory, the file's bytes, its LTTB count, the render's peak memory and
# its render's relative L1 difference from before's (caustix-compare).
#
#   scripts/bench-shared-work.sh [OUT_CSV] [PRESET]   (default docs/results/shared_work.csv, fast)
#
# Needs a built tree (scripts/test.sh or scripts/run-default.sh). About
# 4 minutes on 2 cores.
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
out_csv=${1:-$src/docs/results/shared_work.csv}
preset=${2:-fast}
bin=$src/build
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
peak_kb() { awk '/Maximum resident set size/ {print $6}' "$1"; }

echo "ball,vertices,mode,preset,bake_s,bake_peak_mb,cxb_bytes,lttb_chunks,render_peak_mb,rel_l1_vs_before" > "$out_csv"
for ball in sphere.obj sphere_fine.obj; do
  dir=$tmp/${ball%.obj}
  mkdir -p "$dir"
  python3 "$src/scripts/twelve_balls.py" "$dir" "$ball"
  verts=$(grep -c '^v ' "$src/assets/meshes/$ball")
  for mode in before no-share shared; do
    flag=()
    [ "$mode" = before ] && flag=(--no-share --ltt-rays cgal)
    [ "$mode" = no-share ] && flag=(--no-share)
    baker=$bin/bake/caustix-bake
    [ "$mode" = before ] && baker=${BEFORE:-$baker}
    t0=$(date +%s.%N)
    /usr/bin/time -v "$baker" "$dir/twelve_balls.gltf" -o "$dir/$mode.cxb" --preset "$preset" -q "${flag[@]}" 2> "$dir/$mode.bake.time"
    t1=$(date +%s.%N)
    /usr/bin/time -v "$bin/runtime/caustix-render" "$dir/$mode.cxb" -o "$dir/$mode.exr" --size 640x360 > /dev/null 2> "$dir/$mode.render.time"
    lttb=$("$bin/formats/caustix-inspect" "$dir/$mode.cxb" | grep -c "LTTB" || true)
    same=""
    [ "$mode" != before ] && same=$("$bin/tools/caustix-compare" "$dir/before.exr" "$dir/$mode.exr" | awk '/^relative L1:/ {print $3}')
    printf '%s,%s,%s,%s,%.2f,%.1f,%s,%s,%.1f,%s\n' "$ball" "$verts" "$mode" "$preset" "$(echo "$t1 - $t0" | bc)" \
      "$(echo "$(peak_kb "$dir/$mode.bake.time") / 1024" | bc -l)" "$(stat -c %s "$dir/$mode.cxb")" "$lttb" \
      "$(echo "$(peak_kb "$dir/$mode.render.time") / 1024" | bc -l)" "$same" | tee -a "$out_csv"
  done
done
echo "wrote $out_csv"
