#!/usr/bin/env bash
# Everything CI checks, on a fresh machine: install dependencies, then
#   1. the full build (Release) and its tests: unit, round trip, determinism,
#      golden file, headless render, CLI end to end, viewer under Xvfb;
#   2. what reads untrusted input -- formats/ and its corruption tests, the
#      baker's scene.json and mesh import tests, the mesh corpus imported and
#      baked -- under AddressSanitizer + UBSan (CAUSTIX_PARTS=bake);
#   3. a short libFuzzer run of each fuzz target (clang-14): the .cxb reader,
#      the runtime's loading path, the mesh importer and the glTF importer,
#      seeded with their committed corpora (tests/fuzz/corpus,
#      tests/fuzz/corpus_mesh, tests/fuzz/corpus_gltf) and the regression
#      inputs.
# CAUSTIX_FUZZ_SECONDS (default 30) sets the length of each run in step 3.
set -euo pipefail
cd "$(dirname "$0")/.."
export MESA_SHADER_CACHE_DISABLE=true

bash scripts/setup-deps.sh

echo "== 1/3 full build and tests"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build
(cd build && ctest --output-on-failure)

echo "== 2/3 formats, scene.json and mesh import under AddressSanitizer + UBSan"
# Debug keeps every assertion; -O1 because CGAL's box optimiser (Eigen) runs
# some 100 times slower at -O0 (the mesh corpus: 10 min instead of 1).
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-g -O1" \
  -DCGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE=TRUE -DCAUSTIX_PARTS=bake -DCAUSTIX_SANITIZE=ON >/dev/null
cmake --build build-asan
(cd build-asan && ctest --output-on-failure)

echo "== 3/3 libFuzzer, ${CAUSTIX_FUZZ_SECONDS:-30} s per target"
CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCAUSTIX_PARTS=bake -DCAUSTIX_FUZZ=ON -DCAUSTIX_SANITIZE=ON \
  -DCAUSTIX_FUZZ_SECONDS="${CAUSTIX_FUZZ_SECONDS:-30}" >/dev/null
cmake --build build-fuzz --target fuzz_cxb_reader fuzz_load_scene fuzz_mesh_import fuzz_gltf_import
(cd build-fuzz && ctest --output-on-failure)
