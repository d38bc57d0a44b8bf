#!/usr/bin/python3
"""Plot for docs/runtime-speed.md: ms per frame on a GPU and on llvmpipe,
per scene and caustics method at the balanced preset, from the frames CSVs
scripts/bench-runtime.sh writes.

    scripts/plot_runtime.py GPU_FRAMES.csv LLVMPIPE_FRAMES.csv OUT.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

METHODS = ["none", "levelmap", "uniform", "volumetric", "splat"]


def load(path, size="640x480", preset="balanced"):
    out, renderer = {}, ""
    for r in csv.DictReader(open(path)):
        if r["size"] != size or r["preset"] != preset or "+" in r["label"]:
            continue
        out[(r["label"], r["method"])] = float(r["median_ms"])
        renderer = r["renderer"]
    return out, renderer


def main(gpu_csv, cpu_csv, png):
    gpu, gpu_name = load(gpu_csv)
    cpu, cpu_name = load(cpu_csv)
    scenes = [s for s in dict.fromkeys(k[0] for k in gpu) if any((s, m) in cpu for m in METHODS)]
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.6), sharey=False)
    width = 0.8 / len(METHODS)
    for ax, data, name in ((axes[0], gpu, gpu_name), (axes[1], cpu, cpu_name)):
        for i, m in enumerate(METHODS):
            xs = [j + (i - (len(METHODS) - 1) / 2) * width for j in range(len(scenes))]
            ys = [data.get((s, m), float("nan")) for s in scenes]
            ax.bar(xs, ys, width, label=m)
        ax.set_yscale("log")
        ax.set_xticks(range(len(scenes)))
        ax.set_xticklabels(scenes, rotation=30, ha="right", fontsize=8)
        ax.set_ylabel("ms per frame (median), 640x480")
        ax.set_title(name.split(", OpenGL")[0] if "llvmpipe" in name else name.split("/")[0], fontsize=9)
        ax.grid(axis="y", which="both", alpha=0.3)
    axes[0].legend(fontsize=8, title="caustics method", title_fontsize=8)
    fig.suptitle("caustix runtime, balanced preset: render + glFinish per frame")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main(*sys.argv[1:4])
