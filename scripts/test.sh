#!/usr/bin/env bash
# Everything CI checks, on a fresh machine: install dependencies, then
#   1. the full build (Release) and its tests: unit, round trip, determinism,
#      golden file, headless render, CLI end to end, viewer under Xvfb;
#   2. what reads untrusted input -- formats/ and its corruption tests, the
#      baker's scene.json and mesh import tests, the mesh corpus imported and
#      baked -- under AddressSanitizer + UBSan (clang-14, CAUSTIX_PARTS=bake),
#      and in the same build a short libFuzzer run of each fuzz target: the
#      .cxb reader, the runtime's loading path, the mesh importer and the
#      glTF importer, seeded with their committed corpora (tests/fuzz/corpus,
#      tests/fuzz/corpus_mesh, tests/fuzz/corpus_gltf) and the regression
#      inputs.
# Time on two cores: ctest runs CAUSTIX_TEST_JOBS tests side by side (default:
# the number of cores; each test process has a temporary directory of its
# own), and the sanitizer build compiles and runs its unit tests at the
# lowest priority while the Release build's tests run, on what CPU they
# leave idle; the fuzz runs come last. Each stage ends with its 15 slowest
# tests (scripts/test_times.py).
# CAUSTIX_FUZZ_SECONDS (default 30) sets the length of each fuzz run.
set -euo pipefail
cd "$(dirname "$0")/.."
export MESA_SHADER_CACHE_DISABLE=true
jobs=${CAUSTIX_TEST_JOBS:-$(nproc)}
start=$SECONDS

bash scripts/setup-deps.sh

stage_time() { echo "-- $1: $(( (SECONDS - start) / 60 )) min $(( (SECONDS - start) % 60 )) s since the start"; }

echo "== 1/2 full build and tests"
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DCAUSTIX_COUNT_GL_CALLS=ON >/dev/null
cmake --build build
stage_time "Release build"

# The sanitizer build and its unit tests, niced: they take only the CPU the
# Release tests leave idle (shader compiles, single-threaded set-up, the
# last long test running alone). No test measures time, so sharing the
# machine changes no result. Debug keeps every assertion; -O1 because CGAL
# runs some 100 times slower at -O0; line tables only, as they name the
# file and line in a report at a tenth less compile time and a third of the
# object size of full debug information. -fsanitize=fuzzer-no-link
# (CAUSTIX_FUZZ) instruments the libraries for the fuzz targets; the unit
# tests link the same libraries without libFuzzer.
CC=clang-14 CXX=clang++-14 cmake -S . -B build-san -G Ninja -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-gline-tables-only -O1" \
  -DCGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE=TRUE -DCAUSTIX_PARTS=bake -DCAUSTIX_SANITIZE=ON -DCAUSTIX_FUZZ=ON \
  -DCAUSTIX_FUZZ_SECONDS="${CAUSTIX_FUZZ_SECONDS:-30}" >/dev/null
# In a session of its own, so that a failed stage 1 stops ninja, the
# compilers and the tests with it. A new session is also a new scheduler
# autogroup, which Linux weighs as much as stage 1's whatever the nice
# value of its processes; the group's own nice value is set to 19 too.
# Exit status 90: the build failed.
setsid nice -n 19 bash -c '
  { echo 19 >/proc/self/autogroup; } 2>/dev/null || true
  cmake --build build-san --target caustix_test_binaries >build/build-san.log 2>&1 || exit 90
  echo "-- sanitizer build done after $SECONDS s in the background"
  cd build-san && ctest -j"$1" -E "_short\$" --output-on-failure --output-junit ctest-junit.xml' \
  san-stage "$jobs" >build/san-tests.log 2>&1 &
san=$!

rc=0
# ctest starts the longest tests first when it knows their times; a fresh
# build does not yet, so it starts from the committed ones.
mkdir -p build/Testing/Temporary
[ -e build/Testing/Temporary/CTestCostData.txt ] || cp tests/ctest_cost.txt build/Testing/Temporary/CTestCostData.txt
(cd build && ctest -j"$jobs" --output-on-failure --output-junit ctest-junit.xml) || rc=$?
python3 scripts/test_times.py build/ctest-junit.xml 15
stage_time "Release tests"
if [ "$rc" -ne 0 ]; then
  kill -- -"$san" 2>/dev/null || true
  wait "$san" 2>/dev/null || true
  exit "$rc"
fi

echo "== 2/2 untrusted input under AddressSanitizer + UBSan; libFuzzer, ${CAUSTIX_FUZZ_SECONDS:-30} s per target"
san_rc=0
wait "$san" || san_rc=$?
if [ "$san_rc" -eq 90 ]; then
  cat build/build-san.log
  exit 1
fi
cat build/san-tests.log
python3 scripts/test_times.py build-san/ctest-junit.xml 15
stage_time "sanitizer tests"
[ "$san_rc" -eq 0 ] || rc=$san_rc
# The fuzz runs last a fixed wall-clock time each, so they run in the
# foreground, on a machine no longer shared, and find what they would alone.
(cd build-san && ctest -j"$jobs" -R "_short\$" --output-on-failure --output-junit fuzz-junit.xml) || rc=$?
stage_time "fuzzing"
exit "$rc"
