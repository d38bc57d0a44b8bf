#!/usr/bin/env python3
"""Plots of scripts/bench-frame-cost.sh's CSVs (docs/runtime-speed.md):
frame_cost_memory.png, the engine's GPU memory per effect and scene at
1280 x 800; frame_cost_frames.png, ms per frame per scene and case, before
and after where both builds were measured (the CSV's build column)."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else "docs/results"

rows = list(csv.DictReader(open(os.path.join(out, "frame_cost_memory_llvmpipe.csv"))))
effects = ["level_maps", "shadow_maps", "glass", "caustic_maps", "media", "water", "views", "meshes", "other"]
fig, ax = plt.subplots(figsize=(11, 4.8))
bottom = [0.0] * len(rows)
for e in effects:
    v = [float(r[e]) for r in rows]
    ax.bar([r["scene"] for r in rows], v, bottom=bottom, label=e.replace("_", " "))
    bottom = [b + x for b, x in zip(bottom, v)]
ax.axhline(48, color="k", lw=0.8, ls="--")
ax.text(len(rows) - 0.5, 49, "48 MB", ha="right", va="bottom", fontsize=8)
ax.axhline(96, color="k", lw=0.8, ls=":")
ax.text(len(rows) - 0.5, 97, "96 MB", ha="right", va="bottom", fontsize=8)
ax.set_ylabel("engine GPU memory, MB")
ax.set_title("balanced preset, caustix-render 1280x800 (2x2 supersampled)", fontsize=9)
ax.tick_params(axis="x", rotation=30)
ax.legend(fontsize=7, ncol=3)
fig.tight_layout()
fig.savefig(os.path.join(out, "frame_cost_memory.png"), dpi=110)

frames = list(csv.DictReader(open(os.path.join(out, "frame_cost_llvmpipe.csv"))))
cases = ["animated", "still", "no caustics (still)", "light turning"]
scenes = [s for s in dict.fromkeys(r["scene"] for r in frames if r["case"] in cases)]
builds = [b for b in ("before", "after") if any(r["build"] == b for r in frames)]
fig, ax = plt.subplots(figsize=(10, 4.5))
width = 0.8 / (len(cases) * len(builds))
for ci, case in enumerate(cases):
    for bi, build in enumerate(builds):
        xs, ys = [], []
        for si, s in enumerate(scenes):
            for r in frames:
                if r["scene"] == s and r["case"] == case and r["build"] == build:
                    xs.append(si + (ci * len(builds) + bi - (len(cases) * len(builds) - 1) / 2) * width)
                    ys.append(float(r["median_ms"]))
        ax.bar(xs, ys, width, label=f"{case} ({build})", hatch="//" if build == "before" else None,
               color=f"C{ci}", alpha=0.55 if build == "before" else 1.0)
ax.set_xticks(range(len(scenes)))
ax.set_xticklabels(scenes, rotation=30)
ax.set_yscale("log")
renderer = frames[0]["renderer"].split(",")[0] if frames else ""
ax.set_ylabel(f"ms per frame, 640x480 ({renderer})")
ax.legend(fontsize=7, ncol=2)
fig.tight_layout()
fig.savefig(os.path.join(out, "frame_cost_frames.png"), dpi=110)
print("plot_frame_cost: wrote", os.path.join(out, "frame_cost_memory.png"), "and", os.path.join(out, "frame_cost_frames.png"))
