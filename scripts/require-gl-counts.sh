# Sourced by the benchmarks that report the engine's GL calls: stops with
# exit status 2 unless the build folder $B was configured with
# -DCAUSTIX_COUNT_GL_CALLS=ON (as scripts/test.sh configures build/).
if ! grep -q '^CAUSTIX_COUNT_GL_CALLS:BOOL=ON' "$B/CMakeCache.txt" 2>/dev/null; then
  echo "$(basename "$0"): $B/ is not configured with -DCAUSTIX_COUNT_GL_CALLS=ON; run" \
    "cmake -S . -B $B -DCAUSTIX_COUNT_GL_CALLS=ON && cmake --build $B" >&2
  exit 2
fi
