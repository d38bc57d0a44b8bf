#!/usr/bin/env bash
# Nothing lost: kill caustix-bake with SIGKILL at random moments, many times,
# and check that the output path always holds either the previous complete
# file (byte-identical) or, before the first bake, nothing; never a partial
# file. Usage: kill_test.sh BUILD_DIR SOURCE_DIR [RUNS]
set -u
build=$1
src=$2
runs=${3:-60}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bake=$build/bake/caustix-bake
inspect=$build/formats/caustix-inspect
scene=$src/assets/scenes/thesis_teapot.json  # a bake of about 0.2 s: kills land in every stage
out=$tmp/out.cxb

# Absent before any complete bake.
for i in $(seq 1 5); do
  "$bake" "$scene" -o "$out" -q --map-size 1024 &
  pid=$!
  sleep "0.0$((RANDOM % 9))"
  kill -9 "$pid" 2>/dev/null
  wait "$pid" 2>/dev/null
  if [ -e "$out" ] && ! "$inspect" "$out" >/dev/null; then
    echo "FAIL: partial file after a kill before the first complete bake"
    exit 1
  fi
  rm -f "$out"
done

"$bake" "$scene" -o "$out" -q --map-size 1024 || exit 1
cp "$out" "$tmp/good.cxb"
killed=0
finished=0
for i in $(seq 1 "$runs"); do
  "$bake" "$scene" -o "$out" -q --map-size 1024 &
  pid=$!
  # Random moment within the bake (0 to ~0.3 s).
  sleep "0.$(printf '%03d' $((RANDOM % 300)))"
  if kill -9 "$pid" 2>/dev/null; then killed=$((killed + 1)); else finished=$((finished + 1)); fi
  wait "$pid" 2>/dev/null
  if ! cmp -s "$out" "$tmp/good.cxb"; then
    echo "FAIL: run $i: the output is not the previous complete file"
    exit 1
  fi
done
leftover=$(ls -A "$tmp" | grep -c '\.tmp\.' || true)
echo "kill_test: $runs runs, $killed killed mid-bake, $finished finished first; output always intact;" \
     "$leftover temporary files left by killed runs (never at the output path)"
echo "kill_test: $runs passed, 0 failed"
