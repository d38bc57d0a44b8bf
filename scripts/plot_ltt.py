#!/usr/bin/python3
"""Plot for docs/glass-tables.md from docs/results/ltt_sweep.csv (caustix-bench ltt)."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"sphere": "tab:blue", "sphere_10k": "tab:green", "teapot_solid": "tab:orange"}


def series(rows, mesh, mode, column):
    pts = [(int(r["resolution"]), float(r[column])) for r in rows if r["mesh"] == mesh and r["interpolation"] == mode]
    return [p[0] for p in pts], [p[1] for p in pts]


def main(folder):
    rows = list(csv.DictReader(open(f"{folder}/ltt_sweep.csv")))
    meshes = list(dict.fromkeys(r["mesh"] for r in rows))
    fig, (size, sph, tea) = plt.subplots(1, 3, figsize=(15, 4.5))
    for m in meshes:
        r, mb = series(rows, m, "bicubic", "mb_per_10k_vertices")
        size.plot(r, mb, "-o", ms=3, color=COLOURS.get(m), label=m)
    size.axhline(20, color="k", ls=":", label="target: 20 MB per 10k vertices")
    size.set_xlabel("grid resolution R (R x R directions per vertex)")
    size.set_ylabel("stored MB per 10 000 vertices")
    size.set_title("LTTB size (12-bit fields, zstd)")
    for m in [m for m in meshes if m.startswith("sphere")]:
        for mode, ls in (("bicubic", "-"), ("bilinear", "--")):
            r, mx = series(rows, m, mode, "dir_err_max_deg")
            sph.plot(r, mx, ls, marker="o", ms=3, color=COLOURS.get(m), label=f"{m} {mode}: max")
            r, p99 = series(rows, m, mode, "dir_err_p99_deg")
            sph.plot(r, p99, ls, marker="x", ms=3, color=COLOURS.get(m), alpha=0.5, label=f"{m} {mode}: 99th pct")
    sph.axhline(0.5, color="k", ls=":", label="target: 0.5 deg")
    sph.set_yscale("log")
    sph.set_ylim(0.01, 10)
    sph.set_xlabel("grid resolution R")
    sph.set_ylabel("exit-direction error (deg), cos theta >= 0.3")
    sph.set_title("Look-up vs direct trace: spheres")
    sph.legend(fontsize=6)
    for m in [m for m in meshes if not m.startswith("sphere")]:
        for mode, ls in (("bicubic", "-"), ("bilinear", "--")):
            r, p50 = series(rows, m, mode, "dir_err_p50_deg")
            tea.plot(r, p50, ls, marker="o", ms=3, color=COLOURS.get(m), label=f"{m} {mode}: median")
            r, mean = series(rows, m, mode, "dir_err_mean_deg")
            tea.plot(r, mean, ls, marker="x", ms=3, color="tab:red", label=f"{m} {mode}: mean")
    tea.set_yscale("log")
    tea.set_xlabel("grid resolution R")
    tea.set_ylabel("exit-direction error (deg), cos theta >= 0.3")
    tea.set_title("Look-up vs direct trace: teapot_solid")
    tea.legend(fontsize=6)
    for ax in (size, sph, tea):
        ax.grid(alpha=0.3)
        ax.axvline(20, color="grey", lw=0.8)
    size.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(f"{folder}/ltt_sweep.png", dpi=100)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/results")
