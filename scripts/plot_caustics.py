#!/usr/bin/python3
"""Plots for docs/caustics.md from chapter5_timing.csv (scripts/bench-caustics.sh)."""
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# Tipprasert 2006 tables 5-1 and 5-3 (seconds per frame, GeForce 6800), teapot.
THESIS_N = [3, 8, 16, 32, 64, 100]
THESIS = {
    "thesis level map (normal)": [0.068, 0.144, 0.265, 0.513, 1.007, 1.562],
    "thesis volumetric": [0.13, 0.361, 0.725, 1.391, 2.805, 4.243],
    "thesis smart": [0.053, 0.104, 0.168, 0.34, 0.629, 0.98],
}


def main(folder):
    rows = list(csv.DictReader(open(f"{folder}/chapter5_timing.csv")))
    scenes = sorted({r["label"] for r in rows})
    fig, axes = plt.subplots(1, len(scenes), figsize=(5 * len(scenes), 4.2), squeeze=False)
    for ax, scene in zip(axes[0], scenes):
        series = defaultdict(list)
        for r in rows:
            if r["label"] != scene:
                continue
            name = r["method"] + ("" if r["cull"] == "1" else " (thesis mode, no culling)")
            series[name].append((int(r["planes"]), float(r["median_ms"])))
        for name, pts in sorted(series.items()):
            pts.sort()
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "-o", ms=3, label=name)
        ax.set_title(f"{scene} (llvmpipe, 640x480)")
        ax.set_xlabel("planes n (uniform: n + 1)")
        ax.set_ylabel("ms per frame")
        ax.set_yscale("log")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(f"{folder}/chapter5_timing.png", dpi=100)

    fig, ax = plt.subplots(figsize=(6, 4))
    for name, ys in THESIS.items():
        ax.plot(THESIS_N, [1000 * y for y in ys], ":o", ms=3, label=name)
    teapot = [r for r in rows if r["label"] == "thesis_teapot"]
    for method, cull, name in (("levelmap", "1", "caustix smart + culling"), ("uniform", "0", "caustix uniform, thesis mode"),
                               ("volumetric", "1", "caustix volumetric")):
        pts = sorted((int(r["planes"]), float(r["median_ms"])) for r in teapot if r["method"] == method and r["cull"] == cull)
        if pts:
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "-o", ms=3, label=name + " (llvmpipe)")
    ax.set_xlabel("planes")
    ax.set_ylabel("ms per frame")
    ax.set_yscale("log")
    ax.set_title("Teapot: caustix (llvmpipe) beside the thesis (GeForce 6800)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(f"{folder}/chapter5_vs_thesis.png", dpi=100)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/results")
