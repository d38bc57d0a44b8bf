#!/usr/bin/env bash
# A build farm in miniature: 200 scenes, generated from eight
# canonical scenes with their first light turned 25 ways, baked through the
# installed package's caustix_bake() under Ninja. Measures the whole build
# with 1 and 2 jobs (the parallel speed-up), the no-op rebuild, and that a
# bake is hermetic: run in an empty directory holding only the inputs its
# depfile names (at the same relative places), it writes the same bytes.
#
#   scripts/bench-build-farm.sh [OUT_CSV]     (default docs/results/build_farm.csv)
#
# Needs a built tree (scripts/test.sh or scripts/run-default.sh). About
# 5 minutes on 2 cores.
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
out_csv=${1:-$src/docs/results/build_farm.csv}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$src/build" --prefix "$tmp/prefix" >/dev/null

farm=$tmp/farm
mkdir -p "$farm/scenes"
cp -r "$src/assets/meshes" "$src/assets/textures" "$farm/"
python3 - "$src/assets/scenes" "$farm/scenes" <<'PY'
import json, math, sys
base, out = sys.argv[1], sys.argv[2]
names = ["glass_ball", "wavy_pool", "flat_pool", "thesis_sphere", "default", "mirror_ring", "sphere_waves", "shafts_pool"]
for name in names:
    scene = json.load(open(f"{base}/{name}.json"))
    for k in range(25):
        s = json.loads(json.dumps(scene))
        light = s["lights"][0]
        a = math.radians(3.0 * k)  # the first light turned about the vertical
        if "direction" in light:
            x, y, z = light["direction"]
            light["direction"] = [x * math.cos(a) - z * math.sin(a), y, x * math.sin(a) + z * math.cos(a)]
        if "position" in light:
            light["position"][0] += 0.01 * k
        s["name"] = f"{name}_{k:02d}"
        json.dump(s, open(f"{out}/{name}_{k:02d}.json", "w"), indent=1)
PY
{
  echo "cmake_minimum_required(VERSION 3.20)"
  echo "project(farm CXX)"
  echo "find_package(caustix REQUIRED)"
  for f in "$farm"/scenes/*.json; do
    n=$(basename "$f" .json)
    echo "caustix_bake(bake_$n SCENE scenes/$n.json OUTPUT cxb/$n.cxb PRESET fast)"
  done
} >"$farm/CMakeLists.txt"
scenes=$(ls "$farm"/scenes/*.json | wc -l)

now() { date +%s.%N; }
declare -A full
for jobs in 1 2; do
  rm -rf "$tmp/build"
  cmake -S "$farm" -B "$tmp/build" -G Ninja -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
  t0=$(now)
  ninja -C "$tmp/build" -j "$jobs" >/dev/null
  full[$jobs]=$(echo "$(now) - $t0" | bc)
  echo "bench-build-farm: $scenes scenes, $jobs job(s): ${full[$jobs]} s"
done
t0=$(now)
ninja -C "$tmp/build" >"$tmp/noop.log"
noop=$(echo "$(now) - $t0" | bc)
grep -q "no work to do" "$tmp/noop.log" || { echo "bench-build-farm: the no-op build did work"; cat "$tmp/noop.log"; exit 1; }
echo "bench-build-farm: no-op rebuild: $noop s"

# Hermetic: every 10th scene, baked again in an empty directory holding only
# what its depfile names (the farm's relative layout), gives the same bytes.
hermetic=0 checked=0
for f in "$farm"/scenes/*_0[05].json "$farm"/scenes/*_1[05].json "$farm"/scenes/*_2[0].json; do
  n=$(basename "$f" .json)
  dep=$tmp/build/CMakeFiles/bake_$n.cxb.d
  box=$tmp/hermetic/$n
  rm -rf "$box" && mkdir -p "$box"
  # The depfile's inputs (after the "output:" target), Make-escaped.
  sed -e '1s/^[^:]*://' -e 's/\\$//' "$dep" | tr ' ' '\n' | sed '/^$/d' | while read -r input; do
    rel=${input#"$farm"/}
    [ "$rel" != "$input" ] || { echo "bench-build-farm: $n reads $input, outside the farm"; exit 1; }
    mkdir -p "$box/$(dirname "$rel")"
    cp "$input" "$box/$rel"
  done
  (cd "$box" && "$tmp/prefix/bin/caustix-bake" "scenes/$n.json" -o "$n.cxb" --preset fast -q)
  checked=$((checked + 1))
  if cmp -s "$box/$n.cxb" "$tmp/build/cxb/$n.cxb"; then hermetic=$((hermetic + 1)); else echo "bench-build-farm: $n differs"; fi
done
echo "bench-build-farm: hermetic: $hermetic of $checked bakes byte-identical"
speedup=$(echo "scale=2; ${full[1]} / ${full[2]}" | bc)
{
  echo "scenes,seconds_1_job,seconds_2_jobs,speedup,noop_seconds,hermetic,hermetic_checked,cores"
  printf '%d,%.2f,%.2f,%.2f,%.3f,%d,%d,%d\n' "$scenes" "${full[1]}" "${full[2]}" "$speedup" "$noop" "$hermetic" "$checked" "$(nproc)"
} >"$out_csv"
echo "bench-build-farm: wrote $out_csv"
[ "$hermetic" = "$checked" ]
