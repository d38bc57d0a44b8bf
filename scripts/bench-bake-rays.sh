#!/usr/bin/env bash
# The light-transport tables' ray casting, side by side in one
# run: the same baker with --ltt-rays cgal (CGAL's AABB tree, exact
# predicates: the tables of bakes before Embree) and --ltt-rays embree
# (the default), per kind of glass mesh: a sphere (glass_ball), a prism
# (prism), the teapot (glass_teapot), a closed 82 k-triangle scan-like blob
# (scripts/scan_blob.py), and two whole scenes, 25 dispersive prisms and
# blocks (scripts/dispersive_prisms.py) and twelve copies of a ball
# (scripts/twelve_balls.py). Per row: the whole bake's seconds, the tables'
# seconds, rays cast and rays per second (from --report), the file's bytes.
#
#   scripts/bench-bake-rays.sh [OUT_CSV]   (default docs/results/bake_rays.csv)
#
# BEFORE=/path/to/an/older/caustix-bake adds its default (Embree) bake of
# each scene as rays_engine "embree_before", in the same run.
#
# Needs a built tree. About 10 minutes on 2 cores.
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
out_csv=${1:-$src/docs/results/bake_rays.csv}
bake=$src/build/bake/caustix-bake
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 "$src/scripts/scan_blob.py" "$tmp/blob.obj" --scene "$tmp/scan.json"
mkdir -p "$tmp/prisms" "$tmp/balls"
python3 "$src/scripts/dispersive_prisms.py" "$tmp/prisms"
python3 "$src/scripts/twelve_balls.py" "$tmp/balls"

echo "scene,preset,rays_engine,bake_s,tables_s,tables,rays,rays_per_s,cxb_bytes" > "$out_csv"
run() {  # name scene preset
  for engine in cgal embree ${BEFORE:+embree_before}; do
    t0=$(date +%s.%N)
    if [ "$engine" = embree_before ]; then
      "$BEFORE" "$2" -o "$tmp/out.cxb" --preset "$3" --report "$tmp/r.json" -q
    else
      "$bake" "$2" -o "$tmp/out.cxb" --preset "$3" --ltt-rays "$engine" --report "$tmp/r.json" -q
    fi
    t1=$(date +%s.%N)
    python3 - "$tmp/r.json" "$1" "$3" "$engine" "$(echo "$t1 - $t0" | bc)" "$(stat -c %s "$tmp/out.cxb")" <<'PY' | tee -a "$out_csv"
import json, sys
r = json.load(open(sys.argv[1]))
tables = r["transport"]["tables"]
rays = sum(t["rays"] for t in tables)
secs = sum(t["seconds"] for t in tables)
print("%s,%s,%s,%.2f,%.2f,%d,%d,%.0f,%s" % (sys.argv[2], sys.argv[3], sys.argv[4], float(sys.argv[5]), secs, len(tables), rays,
                                           rays / secs if secs else 0, sys.argv[6]))
PY
  done
}
run sphere "$src/assets/scenes/glass_ball.json" balanced
run prism "$src/assets/scenes/prism.json" balanced
run teapot "$src/assets/scenes/glass_teapot.json" balanced
run scan_82k "$tmp/scan.json" balanced
run dispersive_prisms_25 "$tmp/prisms/scene.json" fast
run twelve_balls "$tmp/balls/twelve_balls.gltf" fast
echo "wrote $out_csv"
/usr/bin/python3 "$src/scripts/plot_bake_rays.py" "$(dirname "$out_csv")"
