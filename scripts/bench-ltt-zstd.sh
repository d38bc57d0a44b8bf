#!/usr/bin/env bash
# The zstd level of the light-transport tables (formats/src/light_transport.cpp,
# kZstdLevel): each table of glass_ball, glass_teapot, prism and a closed
# 82 k-triangle scan-like blob (scripts/scan_blob.py), baked at balanced,
# taken out of its LTTB chunk (formats/SPEC.md: the frame follows 64 bytes
# of fields), decompressed, and compressed again at levels 1..9 by zstd's
# own benchmark (`zstd -b`, one thread, the same library as the baker).
# Per row: the table, its raw bytes, the level, the stored bytes and the
# compression and decompression speeds.
#
#   scripts/bench-ltt-zstd.sh [OUT_CSV]   (default docs/results/ltt_zstd_levels.csv)
#
# Needs a built tree and the zstd command (Debian's zstd). About 3 minutes.
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
out_csv=${1:-$src/docs/results/ltt_zstd_levels.csv}
bake=$src/build/bake/caustix-bake
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 "$src/scripts/scan_blob.py" "$tmp/blob.obj" --scene "$tmp/scan.json"
echo "table,raw_bytes,level,stored_bytes,compress_mb_per_s,decompress_mb_per_s" > "$out_csv"
for scene in "$src/assets/scenes/glass_ball.json" "$src/assets/scenes/glass_teapot.json" "$src/assets/scenes/prism.json" "$tmp/scan.json"; do
  name=$(basename "$scene" .json)
  "$bake" "$scene" -o "$tmp/$name.cxb" --preset balanced -q
  # Every LTTB frame, through the chunk table (32-byte entries after the 64-byte header).
  python3 - "$tmp/$name.cxb" "$tmp/$name" <<'PY'
import struct, sys
b = open(sys.argv[1], "rb").read()
count = struct.unpack_from("<I", b, 24)[0]
k = 0
for i in range(count):
    tag, _, off, size, _ = struct.unpack_from("<4sIQQQ", b, 64 + 32 * i)
    if tag != b"LTTB":
        continue
    n = struct.unpack_from("<I", b, off + 60)[0]
    open("%s.%d.zst" % (sys.argv[2], k), "wb").write(b[off + 64:off + 64 + n])
    k += 1
PY
  for f in "$tmp/$name".*.zst; do
    table=$(basename "$f" .zst)
    zstd -q -d -f "$f" -o "$tmp/raw"
    raw=$(stat -c %s "$tmp/raw")
    for level in 1 2 3 4 5 6 7 8 9; do
      zstd -b"$level" -i1 "$tmp/raw" 2>&1 | tr '\r' '\n' | grep "MB/s, " | tail -1 | sed 's/.*-> *//' |
        awk -v t="$table" -v r="$raw" -v l="$level" '{ split($0, a, /[ ,(x)]+/); printf "%s,%s,%d,%s,%s,%s\n", t, r, l, a[1], a[3], a[5] }' |
        tee -a "$out_csv"
    done
  done
done
echo "wrote $out_csv"
