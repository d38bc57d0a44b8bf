#!/usr/bin/env bash
# A long fuzzing campaign of one target, as docs/robustness.md reports:
#   tests/fuzz/campaign.sh BUILD_FUZZ_DIR TARGET SECONDS [WORK_DIR]
# (BUILD_FUZZ_DIR from scripts/test.sh step 3; TARGET fuzz_cxb_reader,
# fuzz_load_scene, fuzz_mesh_import or fuzz_gltf_import). Starts from the
# target's corpus (tests/fuzz/corpus; tests/fuzz/corpus_mesh for the mesh
# importer, tests/fuzz/corpus_gltf for the glTF importer) and the
# regressions, prints libFuzzer's final statistics, then merges what the run
# found into that corpus (-merge=1 keeps only inputs that add coverage) for
# committing. A crash is written to WORK_DIR/crash-*: minimise it
# (-minimize_crash=1), fix it, and add it to tests/fuzz/regressions.
set -euo pipefail
build=$1
target=$2
seconds=$3
work=${4:-$(mktemp -d)}
here=$(cd "$(dirname "$0")" && pwd)
seeds=$here/corpus
[ "$target" = fuzz_mesh_import ] && seeds=$here/corpus_mesh
[ "$target" = fuzz_gltf_import ] && seeds=$here/corpus_gltf
mkdir -p "$work/corpus"
cp -n "$seeds"/* "$work/corpus/"
ASAN_OPTIONS=detect_leaks=1 "$build/tests/$target" -max_total_time="$seconds" -max_len=65536 \
  -print_final_stats=1 -artifact_prefix="$work/" "$work/corpus" "$here/regressions"
"$build/tests/$target" -merge=1 "$seeds" "$work/corpus"
echo "campaign: corpus in $work/corpus; merged into $seeds ($(ls "$seeds" | wc -l) files)"
