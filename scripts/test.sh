#!/usr/bin/env bash
# Everything CI checks, on a fresh machine: install dependencies, then
#   1. the full build (Release) and its tests: unit, round trip, determinism,
#      golden file, headless render, CLI end to end, viewer under Xvfb;
#   2. formats/ and its corruption tests under AddressSanitizer + UBSan;
#   3. a short libFuzzer run of each fuzz target (clang-14): the .cxb reader
#      and the runtime's loading path, seeded with tests/fuzz/corpus and the
#      regression inputs.
# CAUSTIX_FUZZ_SECONDS (default 30) sets the length of each run in step 3.
set -euo pipefail
cd "$(dirname "$0")/.."
export MESA_SHADER_CACHE_DISABLE=true

bash scripts/setup-deps.sh

echo "== 1/3 full build and tests"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build
(cd build && ctest --output-on-failure)

echo "== 2/3 formats under AddressSanitizer + UBSan"
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCAUSTIX_FORMATS_ONLY=ON -DCAUSTIX_SANITIZE=ON >/dev/null
cmake --build build-asan
(cd build-asan && ctest --output-on-failure)

echo "== 3/3 libFuzzer, ${CAUSTIX_FUZZ_SECONDS:-30} s per target"
CC=clang-14 CXX=clang++-14 cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCAUSTIX_FORMATS_ONLY=ON -DCAUSTIX_FUZZ=ON -DCAUSTIX_SANITIZE=ON \
  -DCAUSTIX_FUZZ_SECONDS="${CAUSTIX_FUZZ_SECONDS:-30}" >/dev/null
cmake --build build-fuzz
(cd build-fuzz && ctest --output-on-failure)
