#!/usr/bin/env bash
# End-to-end checks of the real binaries: exit codes, error messages, atomic
# output, inspect, headless render and the viewer under Xvfb.
# Usage: cli_test.sh BUILD_DIR SOURCE_DIR [PART]
# PART is bake (the baker's options, errors, budgets, sharing), render
# (inspect, caustix-render, caustix-compare) or view (the viewer); all three
# when absent. ctest runs the parts as three tests side by side.
set -u
build=$1
src=$2
part=${3:-all}
case "$part" in all|bake|render|view) ;; *) echo "cli_test: unknown part '$part'"; exit 2;; esac
want() { [ "$part" = all ] || [ "$part" = "$1" ]; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bake=$build/bake/caustix-bake
render=$build/runtime/caustix-render
view=$build/runtime/caustix-view
inspect=$build/formats/caustix-inspect
scene=$src/assets/scenes/default.json
passed=0
failed=0

check() {  # check NAME EXPECTED_RC ACTUAL_RC
  if [ "$2" = "$3" ]; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: $1 (exit $3, expected $2)"; fi
}
contains() {  # contains NAME FILE TEXT
  if grep -qF -- "$3" "$2"; then passed=$((passed + 1)); else failed=$((failed + 1)); echo "FAIL: $1: '$3' not in:"; cat "$2"; fi
}

if want bake; then
# --help and --version
"$bake" --help >"$tmp/help" 2>&1; check "bake --help" 0 $?
contains "help lists defaults" "$tmp/help" "--position-bits"
contains "help lists exit codes" "$tmp/help" "Exit codes"
"$bake" --version >"$tmp/v" 2>&1; check "bake --version" 0 $?
"$bake" --bogus "$scene" -o "$tmp/x.cxb" 2>"$tmp/err"; check "unknown option" 2 $?
contains "unknown option named" "$tmp/err" "--bogus"
"$bake" "$scene" -o "$tmp/x.cxb" --position-bits 99 2>"$tmp/err"; check "out-of-range option" 2 $?

# A good bake, twice: byte-identical; depfile and report.
"$bake" "$scene" -o "$tmp/a.cxb" --depfile "$tmp/a.d" --report "$tmp/a.json" -q; check "bake" 0 $?
"$bake" "$scene" -o "$tmp/b.cxb" -q; check "bake again" 0 $?
cmp -s "$tmp/a.cxb" "$tmp/b.cxb"; check "bakes are byte-identical" 0 $?
# Hermetic: the bytes do not depend on the directory the bake
# runs in or on how the scene's path is spelled (TEXR once recorded the
# textures' paths as resolved from there).
(cd "$src/assets" && "$bake" scenes/default.json -o "$tmp/cwd.cxb" -q); check "bake from another directory" 0 $?
cmp -s "$tmp/a.cxb" "$tmp/cwd.cxb"; check "same bytes from another directory" 0 $?
contains "depfile lists the scene" "$tmp/a.d" "default.json"
contains "depfile lists meshes" "$tmp/a.d" "sphere.obj"
contains "depfile lists textures" "$tmp/a.d" "pool_tiles.png"
contains "report has meshes" "$tmp/a.json" "draco_bytes"
contains "report says the bake succeeded" "$tmp/a.json" '"status": "ok"'
contains "report has level maps" "$tmp/a.json" "planes_smart"
"$bake" "$scene" -o "$tmp/v.cxb" -v --map-size 64 >"$tmp/vout"; check "bake -v" 0 $?
contains "verbose shows the depth profile" "$tmp/vout" "levels empty"
contains "verbose shows skipped pairs or maps" "$tmp/vout" "level map ball / light 0"
"$bake" "$scene" -o "$tmp/u.cxb" --slicing uniform --planes 8 --levels 16 --map-size 32 --threads 1 -q; check "bake uniform" 0 $?
"$bake" "$scene" -o "$tmp/u2.cxb" --slicing uniform --planes 8 --levels 16 --map-size 32 --threads 2 -q; check "bake 2 threads" 0 $?
cmp -s "$tmp/u.cxb" "$tmp/u2.cxb"; check "1 and 2 threads byte-identical" 0 $?
# Presets (docs/tradeoff.md): the preset's knobs unless given explicitly, and
# its runtime defaults recorded in the file (RNDR) for the renderers.
"$bake" "$scene" -o "$tmp/fast.cxb" --preset fast --planes 5 --report "$tmp/fast.json" -q; check "bake --preset fast" 0 $?
python3 -c "import json,sys; o=json.load(open(sys.argv[1]))['options']; assert o['planes'] == 5 and o['water_grid_scale'] == 0.5 and o['levels'] == 64, o" "$tmp/fast.json"
check "preset applied, explicit --planes wins" 0 $?
"$inspect" "$tmp/fast.cxb" >"$tmp/out"; check "inspect preset file" 0 $?
contains "preset's runtime defaults recorded" "$tmp/out" "render defaults (preset 'fast'): caustics map 512^2, glass textures 256^2"
"$inspect" "$tmp/a.cxb" >"$tmp/out"
! grep -q RNDR "$tmp/out"; check "no RNDR chunk without a preset" 0 $?
"$bake" "$scene" -o "$tmp/x.cxb" --preset turbo 2>"$tmp/err"; check "unknown preset" 2 $?
contains "unknown preset named" "$tmp/err" "turbo"
"$bake" "$scene" -o "$tmp/x.cxb" --slicing diagonal 2>/dev/null; check "bad slicing" 2 $?
"$bake" "$scene" -o "$tmp/x.cxb" --levels 0 2>/dev/null; check "bad levels" 2 $?
"$bake" "$scene" -o "$tmp/x.cxb" --map-size 9000 2>/dev/null; check "map too large" 2 $?

# glTF 2.0 (docs/scene-format.md): the glass ball baked straight from its
# .gltf and rendered; a scene.json importing a .glb beside its own water; a
# broken glTF refused by pointer with nothing written.
gltf=$src/assets/gltf/glass_ball.gltf
"$bake" "$gltf" -o "$tmp/g.cxb" --depfile "$tmp/g.d" --ltt-resolution 8 -q; check "bake a .gltf" 0 $?
contains "depfile lists the glTF" "$tmp/g.d" "glass_ball.gltf"
"$render" "$tmp/g.cxb" -o "$tmp/g.png" --size 96x64 -q; check "render a baked .gltf" 0 $?
"$bake" "$gltf" -o "$tmp/g2.cxb" --ltt-resolution 8 --threads 1 -q; check "bake a .gltf again" 0 $?
cmp -s "$tmp/g.cxb" "$tmp/g2.cxb"; check "glTF bakes are byte-identical" 0 $?
cp "$gltf" "$tmp/ball.gltf"
printf '{"gltf": "ball.gltf", "water": {"level": 1.6, "grid": {"cells": [16, 16], "extent": [-2, -2, 2, 2]}}}' >"$tmp/withwater.json"
"$bake" "$tmp/withwater.json" -o "$tmp/w.cxb" --depfile "$tmp/w.d" --ltt-resolution 8 -q; check "scene.json importing a glTF" 0 $?
contains "depfile lists the imported glTF" "$tmp/w.d" "ball.gltf"
"$inspect" "$tmp/w.cxb" >"$tmp/out"; contains "imported objects and water" "$tmp/out" "WATR"
sed 's/"mesh": 1,/"mesh": 7,/' "$gltf" >"$tmp/bad.gltf"
"$bake" "$tmp/bad.gltf" -o "$tmp/bg.cxb" 2>"$tmp/err"; check "bad glTF" 3 $?
contains "bad glTF names the pointer" "$tmp/err" "/nodes/1/mesh: mesh 7 does not exist"
[ ! -e "$tmp/bg.cxb" ]; check "no output for a bad glTF" 0 $?

# Bad input: clear error naming the place, exit 3, old output untouched, no temp files left.
cp "$tmp/a.cxb" "$tmp/keep.cxb"
printf '{\n  "objects": [ { "name": "a", "mesh": 5 } ]\n}\n' >"$tmp/bad.json"
"$bake" "$tmp/bad.json" -o "$tmp/keep.cxb" --report "$tmp/bad_report.json" 2>"$tmp/err"; check "bad scene" 3 $?
contains "a scene that does not parse fails in the scene stage" "$tmp/bad_report.json" '"stage": "scene"'
contains "error has line:column" "$tmp/err" "bad.json:2:31: /objects/0/mesh"
cmp -s "$tmp/a.cxb" "$tmp/keep.cxb"; check "old output untouched" 0 $?
"$bake" "$tmp/missing.json" -o "$tmp/m.cxb" 2>"$tmp/err"; check "missing scene" 3 $?
[ ! -e "$tmp/m.cxb" ]; check "no output on failure" 0 $?
printf '{"objects": [{"name": "a", "mesh": "gone.obj"}]}' >"$tmp/nomesh.json"
"$bake" "$tmp/nomesh.json" -o "$tmp/m.cxb" 2>"$tmp/err"; check "missing mesh" 3 $?
contains "missing mesh named" "$tmp/err" "gone.obj: mesh file not found"
# Warnings are said as they are found, so a bake that fails later
# has said them; its --report says what it had done and where it failed.
printf '{"objects": [{"name": "a", "mesh": "%s"}, {"name": "b", "mesh": "gone.obj"}]}' \
  "$src/tests/data/meshes/obj_faces_under_three_vertices.obj" >"$tmp/warnfail.json"
"$bake" "$tmp/warnfail.json" -o "$tmp/m.cxb" --report "$tmp/fail.json" 2>"$tmp/err"; check "warning, then a missing mesh" 3 $?
contains "the first mesh's warning is said before the error" "$tmp/err" "skipped 2 face(s)"
python3 -c "
import json, sys
r = json.load(open(sys.argv[1]))
assert r['status'] == 'failed' and r['exit_code'] == 3 and 'gone.obj' in r['error'], r
assert r['failed_in'] == {'stage': 'meshes', 'item': r['failed_in']['item']} and r['failed_in']['item'].endswith('gone.obj'), r
assert any('skipped 2 face(s)' in w for w in r['warnings']), r" "$tmp/fail.json"
check "a failed bake's report" 0 $?
[ ! -e "$tmp/m.cxb" ]; check "no output after the warning and the failure" 0 $?
# Budgets: past --max-seconds or --max-memory the bake stops with
# exit code 7, names the stage and the option to lower, and writes nothing.
"$bake" "$src/assets/scenes/glass_ball.json" -o "$tmp/m.cxb" --max-seconds 0.001 --report "$tmp/fail.json" 2>"$tmp/err"
check "--max-seconds stops the bake" 7 $?
contains "the time budget is named" "$tmp/err" "past --max-seconds 0.001; lower"
contains "its report says it failed" "$tmp/fail.json" '"status": "failed"'
"$bake" "$src/assets/scenes/glass_ball.json" -o "$tmp/m.cxb" --max-memory 1MB 2>"$tmp/err"; check "--max-memory stops the bake" 7 $?
contains "the memory budget is named" "$tmp/err" "past --max-memory 1 MiB; lower"
[ ! -e "$tmp/m.cxb" ]; check "no output from a stopped bake" 0 $?
"$bake" "$scene" -o "$tmp/m.cxb" --max-memory 1TB --max-seconds 3600 -q; check "generous budgets change nothing" 0 $?
cmp -s "$tmp/a.cxb" "$tmp/m.cxb"; check "the same bytes under a budget" 0 $?
"$bake" "$scene" -o "$tmp/m.cxb" --max-memory lots 2>/dev/null; check "a malformed --max-memory" 2 $?
# Progress: in a log, a plain line per stage and item; nothing with -q.
"$bake" "$src/assets/scenes/glass_ball.json" -o "$tmp/g.cxb" 2>"$tmp/prog"; check "bake glass_ball" 0 $?
contains "progress names the stage and the object" "$tmp/prog" "caustix-bake: light-transport tables: ball 0 %"
contains "progress names the meshes" "$tmp/prog" "caustix-bake: meshes: "
! grep -q $'\r' "$tmp/prog"; check "no carriage returns in a log" 0 $?
"$bake" "$scene" -o "$tmp/q.cxb" -q 2>"$tmp/prog"; check "bake -q" 0 $?
[ ! -s "$tmp/prog" ]; check "nothing on stderr with -q" 0 $?
# Shared work: a turned copy of the ball uses the ball's table
# (LTTR), which inspect and the report name; --no-share gives it its own;
# --ltt-rays picks the tables' caster.
python3 - "$src/assets/scenes/glass_ball.json" "$tmp/twins.json" <<'PY'
import json, os, sys
s = json.load(open(sys.argv[1]))
for o in s["objects"]:
    o["mesh"] = os.path.join(os.path.dirname(sys.argv[1]), o["mesh"])
twin = json.loads(json.dumps(s["objects"][1]))
twin["name"] = "twin"
twin["transform"] = {"translate": [1.2, 0.5, 0], "rotate_deg": [30, 40, 0], "scale": 0.3}
s["objects"].append(twin)
json.dump(s, open(sys.argv[2], "w"))
PY
"$bake" "$tmp/twins.json" -o "$tmp/twins.cxb" --ltt-resolution 8 --report "$tmp/twins_report.json" -q; check "bake copies of a ball" 0 $?
"$inspect" "$tmp/twins.cxb" >"$tmp/out"; check "inspect copies" 0 $?
contains "one table for both (LTTR)" "$tmp/out" "LTTR"
contains "inspect names the shared table" "$tmp/out" "tables of ball"
contains "the report names the sharer" "$tmp/twins_report.json" '"twin": "ball"'
"$bake" "$tmp/twins.json" -o "$tmp/twins_own.cxb" --ltt-resolution 8 --no-share -q; check "bake copies --no-share" 0 $?
"$inspect" "$tmp/twins_own.cxb" >"$tmp/out"; check "inspect --no-share copies" 0 $?
! grep -q "LTTR" "$tmp/out"; check "no LTTR with --no-share" 0 $?
[ "$(stat -c %s "$tmp/twins.cxb")" -lt "$(stat -c %s "$tmp/twins_own.cxb")" ]; check "sharing makes the file smaller" 0 $?
"$bake" "$tmp/twins.json" -o "$tmp/twins_cgal.cxb" --ltt-resolution 8 --ltt-rays cgal -q; check "--ltt-rays cgal" 0 $?
contains "the report names the caster" "$tmp/twins_report.json" '"rays": "embree"'
"$bake" "$tmp/twins.json" -o "$tmp/x.cxb" --ltt-rays optix 2>"$tmp/err"; check "an unknown --ltt-rays" 2 $?
contains "the choices are named" "$tmp/err" "optix not in {embree,cgal}"
"$bake" "$scene" -o "$tmp/no/such/dir/x.cxb" 2>"$tmp/err"; check "unwritable output" 5 $?
[ -z "$(ls -A "$tmp" | grep '\.tmp\.')" ]; check "no temporary files left" 0 $?
fi

# What the render and view parts read: the default scene, and its fast preset
# (the bake part made them already when it ran).
if ! want bake; then
  "$bake" "$scene" -o "$tmp/a.cxb" -q; check "bake" 0 $?
  "$bake" "$scene" -o "$tmp/fast.cxb" --preset fast --planes 5 -q; check "bake --preset fast" 0 $?
fi

if want render; then

# inspect
"$inspect" "$tmp/a.cxb" >"$tmp/out"; check "inspect" 0 $?
contains "inspect shows chunks" "$tmp/out" "MESH"
contains "inspect shows level maps" "$tmp/out" "planes uniform 33 / smart"
"$inspect" --json "$tmp/a.cxb" >"$tmp/out.json"; check "inspect --json" 0 $?
python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['valid'] and len(d['chunks'])>5" "$tmp/out.json"
check "inspect json parses" 0 $?
cp "$tmp/a.cxb" "$tmp/corrupt.cxb"
printf '\x55' | dd of="$tmp/corrupt.cxb" bs=1 seek=2000 conv=notrunc 2>/dev/null
"$inspect" "$tmp/corrupt.cxb" >"$tmp/out"; check "inspect corrupt" 4 $?
contains "corruption named" "$tmp/out" "checksum mismatch"
head -c 1000 "$tmp/a.cxb" >"$tmp/trunc.cxb"

# render: PNG and EXR, and clear failures on bad files
"$render" "$tmp/a.cxb" -o "$tmp/img.png" --size 160x120 -q; check "render png" 0 $?
"$render" "$tmp/a.cxb" -o "$tmp/img.exr" --size 64 --time 2 -q; check "render exr" 0 $?
iinfo "$tmp/img.png" >"$tmp/info" 2>&1; contains "png size" "$tmp/info" "160 x  120"
iinfo "$tmp/img.exr" >"$tmp/info" 2>&1; contains "exr is float" "$tmp/info" "float"
"$render" "$tmp/trunc.cxb" -o "$tmp/t.png" 2>"$tmp/err"; check "render truncated" 4 $?
contains "truncation named" "$tmp/err" "truncated"
[ ! -e "$tmp/t.png" ]; check "no image on failure" 0 $?
"$render" "$tmp/corrupt.cxb" -o "$tmp/t.png" 2>/dev/null; check "render corrupt" 4 $?
"$render" "$tmp/a.cxb" -o "$tmp/t.png" --size 0x5 2>/dev/null; check "render bad size" 2 $?
"$render" "$tmp/a.cxb" -o "$tmp/t.unknownext" 2>/dev/null; check "render bad extension" 5 $?

# One step from a scene or glTF file to a picture (docs/tools.md): baked
# in-process into the cache on the first open -- the bytes caustix-bake
# writes -- and reused while no file it was baked from changes.
cache=$tmp/cache
cp "$src/assets/gltf/glass_ball.gltf" "$tmp/open.gltf"
"$render" "$tmp/open.gltf" -o "$tmp/o1.png" --size 96x64 --cache "$cache" 2>"$tmp/err"; check "render a .gltf" 0 $?
contains "a cold cache bakes" "$tmp/err" "baked in"
"$bake" "$tmp/open.gltf" -o "$tmp/open.cxb" -q; check "bake the .gltf" 0 $?
cmp -s "$tmp/open.cxb" "$cache"/*.cxb; check "the cache holds caustix-bake's bytes" 0 $?
"$render" "$tmp/open.gltf" -o "$tmp/o2.png" --size 96x64 --cache "$cache" -v >"$tmp/out" 2>&1; check "render it again" 0 $?
contains "a warm cache is reused" "$tmp/out" "baked before"
cmp -s "$tmp/o1.png" "$tmp/o2.png"; check "the same picture from the cache" 0 $?
sed -i 's/"name": "ball"/"name": "glass ball"/' "$tmp/open.gltf"
"$render" "$tmp/open.gltf" -o "$tmp/o3.png" --size 96x64 --cache "$cache" 2>"$tmp/err"; check "render the changed .gltf" 0 $?
contains "a changed file is baked again" "$tmp/err" "baked in"
"$render" "$tmp/open.gltf" -o "$tmp/o4.png" --size 96x64 --cache "$cache" --bake-preset fast -q; check "another preset" 0 $?
[ "$(ls "$cache"/*.cxb | wc -l)" = 3 ]; check "an entry per contents and options" 0 $?
# A file without lights: the default rig, said; --no-default-light: dark.
python3 -c "
import json, sys
d = json.load(open(sys.argv[1]))
d['extensionsUsed'].remove('KHR_lights_punctual'); del d['extensions']
for n in d['nodes']: n.pop('extensions', None)
json.dump(d, open(sys.argv[2], 'w'))" "$src/assets/gltf/glass_ball.gltf" "$tmp/unlit.gltf"
"$render" "$tmp/unlit.gltf" -o "$tmp/rig.png" --size 96x64 --cache "$cache" 2>"$tmp/err"; check "render a file without lights" 0 $?
contains "the default rig is said" "$tmp/err" "the file has no lights; lit by the default rig"
"$render" "$tmp/unlit.gltf" -o "$tmp/dark.png" --size 96x64 --cache "$cache" --no-default-light 2>"$tmp/err"
check "--no-default-light" 0 $?
contains "dark, and said" "$tmp/err" "the scene has no lights; everything will be dark"
# The sun lights the floor: its irradiance / E0 is sin 55 deg = 0.82 in the
# open, less in the ball's shadow (the mean over the region measured 0.77);
# without a light it is 0.
for light in rig dark; do
  flag=; [ $light = dark ] && flag=--no-default-light
  "$render" "$tmp/unlit.gltf" -o "$tmp/$light.exr" --irradiance floor --region -1,-1,1,1 --size 16x16 --cache "$cache" -q $flag
done
python3 -c "
import subprocess, sys
def mean(f):
    out = subprocess.run(['oiiotool', f, '--printstats'], capture_output=True, text=True).stdout
    return float([l for l in out.splitlines() if 'Stats Avg' in l][0].split(':')[1].split()[0])
sys.exit(0 if 0.6 < mean(sys.argv[1]) < 0.82 and mean(sys.argv[2]) == 0 else 1)" "$tmp/rig.exr" "$tmp/dark.exr"
check "the default rig lights the scene" 0 $?
# Failures: a broken glTF named by pointer, exit 3, no image and no entry;
# a cache that cannot be made, exit 5.
sed 's/"mesh": 1,/"mesh": 7,/' "$src/assets/gltf/glass_ball.gltf" >"$tmp/broken.gltf"
entries=$(ls "$cache" | wc -l)
"$render" "$tmp/broken.gltf" -o "$tmp/b.png" --cache "$cache" 2>"$tmp/err"; check "render a broken glTF" 3 $?
contains "the broken glTF's pointer" "$tmp/err" "/nodes/1/mesh: mesh 7 does not exist"
[ ! -e "$tmp/b.png" ] && [ "$(ls "$cache" | wc -l)" = "$entries" ]; check "no image, no entry" 0 $?
"$render" "$tmp/open.gltf" -o "$tmp/b.png" --cache /proc/caustix-cache -q 2>"$tmp/err"; check "an unwritable cache" 5 $?
contains "the cache named" "$tmp/err" "/proc/caustix-cache"
"$render" "$tmp/open.gltf" -o "$tmp/b.png" --bake-preset slow 2>/dev/null; check "an unknown bake preset" 2 $?

# irradiance images and caustix-compare
compare=$build/tools/caustix-compare
"$render" "$tmp/a.cxb" --irradiance floor --region -1,-1,1,1 --size 32 -o "$tmp/irr.exr" -q; check "render irradiance" 0 $?
"$render" "$tmp/a.cxb" --irradiance floor --region -1,-1,1,1 --size 32 --method none -o "$tmp/irr_none.exr" -q; check "render irradiance none" 0 $?
"$render" "$tmp/fast.cxb" --irradiance floor --region -1,-1,1,1 --size 32 -o "$tmp/irr_fast.exr" -v >"$tmp/rout"; check "render a preset file" 0 $?
contains "renderer starts from the preset's defaults" "$tmp/rout" "glass textures 256^2"
"$render" "$tmp/fast.cxb" --irradiance floor --region -1,-1,1,1 --size 32 --caustics-size 100 -o "$tmp/irr_fast.exr" -v >"$tmp/rout"
contains "explicit --caustics-size wins" "$tmp/rout" "caustics map 100^2"
"$render" "$tmp/a.cxb" --irradiance nosuch -o "$tmp/x.exr" 2>"$tmp/err"; check "unknown receiver" 2 $?
contains "receiver named" "$tmp/err" "no object named 'nosuch'"
"$compare" "$tmp/irr.exr" "$tmp/irr.exr" >"$tmp/cmp"; check "compare itself" 0 $?
contains "compare itself is 0" "$tmp/cmp" "eq. 2-9 (mean CIE Luv difference): 0"
"$compare" --json "$tmp/irr.exr" "$tmp/irr_none.exr" >"$tmp/cmp.json"; check "compare json" 0 $?
python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['eq29'] > 0 and 'peak_error_m' in d" "$tmp/cmp.json"
check "caustics differ from none" 0 $?
"$compare" "$tmp/irr.exr" "$tmp/img.exr" 2>/dev/null; check "compare size mismatch" 4 $?
"$compare" "$tmp/irr.exr" "$tmp/nope.exr" 2>/dev/null; check "compare missing file" 3 $?

# in-scatter images (media, Pfeuti): a scene without media is refused by
# name; fog_ball's image is written with its energy balance; the fast
# preset's media defaults travel in the file and explicit options win
"$render" "$tmp/a.cxb" --inscatter --region -1,0,1,2 --size 16 -o "$tmp/ins.exr" 2>"$tmp/err"; check "in-scatter without media" 2 $?
contains "in-scatter refusal names the reason" "$tmp/err" "nothing in the scene scatters"
"$bake" "$src/assets/scenes/fog_ball.json" -o "$tmp/fog.cxb" --preset fast -q; check "bake fog_ball (fast)" 0 $?
"$render" "$tmp/fog.cxb" --inscatter --region -1.5,0,1.5,2.5 --size 24x20 -o "$tmp/ins.exr" -v >"$tmp/rout"; check "render in-scatter" 0 $?
# 128^2 over the light's window and (128/2)^2 over the glass's (focus grid)
contains "in-scatter uses the preset's photons" "$tmp/rout" "20480 photons (4096 over the glass)"
contains "in-scatter prints the energy balance" "$tmp/rout" "energy / E0"
"$render" "$tmp/fog.cxb" --inscatter --region -1.5,0,1.5,2.5 --size 24x20 --volume-grid 2000 -o "$tmp/ins.exr" 2>/dev/null
check "in-scatter grid out of range" 2 $?
"$render" "$tmp/fog.cxb" --inscatter --region -1.5,0,1.5,2.5 --size 24x20 --volume-photons 64 -o "$tmp/ins.exr" -v >"$tmp/rout"
contains "explicit --volume-photons wins" "$tmp/rout" "5120 photons (1024 over the glass)"
"$render" "$tmp/fog.cxb" --inscatter --region 1,1,0,0 --size 8 -o "$tmp/ins.exr" 2>/dev/null; check "in-scatter bad region" 2 $?

fi

if want view; then
# viewer: opens a window under Xvfb and saves a screenshot
if command -v xvfb-run >/dev/null; then
  xvfb-run -a -s "-screen 0 640x480x24" "$view" "$tmp/a.cxb" --size 320x240 --frames 3 --screenshot "$tmp/shot.png" >"$tmp/vout" 2>&1
  check "viewer screenshot under Xvfb" 0 $?
  iinfo "$tmp/shot.png" >"$tmp/info" 2>&1; contains "screenshot size" "$tmp/info" "320 x  240"
  # The panel (Dear ImGui) is in the screenshot, and the interactive water
  # runs with a ripple dropped: the panel's corner differs from --no-ui's.
  xvfb-run -a -s "-screen 0 800x600x24" "$view" "$tmp/a.cxb" --size 640x480 --frames 4 --simulate --ripple 0.3,0.2 \
    --screenshot "$tmp/ui.png" >"$tmp/vout" 2>&1
  check "viewer with panel and interactive water" 0 $?
  xvfb-run -a -s "-screen 0 800x600x24" "$view" "$tmp/a.cxb" --size 640x480 --frames 4 --simulate --ripple 0.3,0.2 \
    --no-ui --screenshot "$tmp/noui.png" >"$tmp/vout" 2>&1
  check "viewer without panel" 0 $?
  oiiotool "$tmp/ui.png" --cut 200x150+20+40 -o "$tmp/ui_corner.png" && oiiotool "$tmp/noui.png" --cut 200x150+20+40 -o "$tmp/noui_corner.png"
  idiff -fail 0.05 -failpercent 20 "$tmp/ui_corner.png" "$tmp/noui_corner.png" >/dev/null 2>&1
  check "the panel is drawn (its corner differs from --no-ui)" 2 $?
  "$view" "$tmp/a.cxb" --ripple 1,2,3 --frames 1 --screenshot "$tmp/s.png" 2>"$tmp/err"; check "viewer bad --ripple" 2 $?
  # A glTF file opened straight away, through the bake cache.
  xvfb-run -a -s "-screen 0 640x480x24" "$view" "$src/assets/gltf/glass_ball.gltf" --cache "$tmp/cache" --size 160x120 \
    --frames 2 --screenshot "$tmp/gshot.png" >"$tmp/vout" 2>&1
  check "viewer opens a .gltf" 0 $?
  contains "the viewer baked it" "$tmp/vout" "baked in"
else
  failed=$((failed + 1)); echo "FAIL: xvfb-run missing (scripts/setup-deps.sh installs it)"
fi
env -u DISPLAY -u WAYLAND_DISPLAY "$view" "$tmp/a.cxb" --frames 1 --screenshot "$tmp/s.png" 2>"$tmp/err"; check "viewer without display" 6 $?
fi

echo "cli_test ($part): $passed passed, $failed failed"
[ "$failed" -eq 0 ]
