#!/usr/bin/env python3
"""Plot of scripts/bench-scale.sh's CSV (docs/runtime-speed.md, "As the
scene grows"): scale.png, against the receivers under the water (one
light): the frame's time over the frame without caustics, draws plus
dispatches, GPU memory at 1280 x 800 and shader invocations. Where
OUT/scale_before_<renderer>.csv exists (the same benchmark of an earlier
build, run beside it), it is drawn in grey; where
OUT/scale_batched_<renderer>.csv exists (the same build with the level
maps in batches, --map-batching always), in purple."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else "docs/results"
renderer = sys.argv[2] if len(sys.argv) > 2 else "llvmpipe"
rows = list(csv.DictReader(open(os.path.join(out, f"scale_{renderer}.csv"))))
before_path = os.path.join(out, f"scale_before_{renderer}.csv")
before = list(csv.DictReader(open(before_path))) if os.path.exists(before_path) else []
batched_path = os.path.join(out, f"scale_batched_{renderer}.csv")
batched = list(csv.DictReader(open(batched_path))) if os.path.exists(batched_path) else []
one = [r for r in rows if r["lights"] == "1"]
n = [int(r["receivers"]) for r in one]
fig, axes = plt.subplots(1, 4, figsize=(15, 3.6))
panels = [
    ("ratio", "frame / frame without caustics"),
    ("caustics_draws_dispatches", "water caustics' draws + dispatches"),
    ("gpu_mb_1280x800", "engine GPU memory at 1280x800, MB"),
    ("fs_invocations", "fragment-shader invocations"),
]
for ax, (key, label) in zip(axes, panels):
    if before and key in before[0]:
        b1 = [r for r in before if r["lights"] == "1"]
        ax.plot([int(r["receivers"]) for r in b1], [float(r[key]) for r in b1], "o--", color="0.6", label="before, 1 light")
        bm = [r for r in before if r["lights"] != "1"]
        ax.plot([int(r["receivers"]) for r in bm], [float(r[key]) for r in bm], "s", color="0.6", label="before, more lights")
    ax.plot(n, [float(r[key]) for r in one], "o-", label="1 light")
    if batched:
        c1 = [r for r in batched if r["lights"] == "1"]
        ax.plot([int(r["receivers"]) for r in c1], [float(r[key]) for r in c1], "o--", color="tab:purple", label="in batches, 1 light")
    for lights in sorted({r["lights"] for r in rows} - {"1"}):
        more = [r for r in rows if r["lights"] == lights]
        ax.plot([int(r["receivers"]) for r in more], [float(r[key]) for r in more], "s", label=f"{lights} lights")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("objects on the pool's floor")
    ax.set_ylabel(label)
    ax.grid(alpha=0.3)
axes[0].legend(fontsize=8)
fig.suptitle(f"scripts/bench-scale.sh, balanced preset, 640x480, {one[0]['renderer'] if one else renderer}", fontsize=9)
fig.tight_layout()
fig.savefig(os.path.join(out, "scale.png"), dpi=110)
print("wrote", os.path.join(out, "scale.png"))
