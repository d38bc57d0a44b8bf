#!/usr/bin/env bash
# Regenerates docs/results/ltt_sweep.csv (light-transport table size, bake
# time and look-up error against grid resolution, caustix-bench ltt) and
# its plot ltt_sweep.png (docs/glass-tables.md shows them). Needs a built tree
# (scripts/test.sh or scripts/run-default.sh); installs python3-matplotlib
# if missing.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! /usr/bin/python3 -c "import matplotlib" 2>/dev/null; then
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get install -y -qq --no-install-recommends python3-matplotlib >/dev/null
fi
cmake --build build --target caustix-bench
mkdir -p docs/results
./build/tools/caustix-bench ltt --resolutions 6,8,10,12,14,16,18,20,24,28,32 --samples 4000 \
  --csv docs/results/ltt_sweep.csv
/usr/bin/python3 scripts/plot_ltt.py docs/results
