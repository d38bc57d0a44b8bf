#!/usr/bin/env bash
# Regenerates docs/results/bake_stages.csv, table_5_4.csv and their plots
# (docs/level-maps.md shows them). Needs a built tree (scripts/test.sh or
# scripts/run-default.sh) and installs python3-matplotlib if missing.
set -euo pipefail
cd "$(dirname "$0")/.."
export MESA_SHADER_CACHE_DISABLE=true
if ! /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get install -y -qq --no-install-recommends python3-matplotlib >/dev/null
fi
cmake --build build --target caustix-bench
mkdir -p docs/results
./build/tools/caustix-bench bake-stages --repeat 7 --csv docs/results/bake_stages.csv
./build/tools/caustix-bench table-5-4 --csv docs/results/table_5_4.csv
/usr/bin/python3 scripts/plot_level_maps.py docs/results
