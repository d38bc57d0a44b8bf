#!/usr/bin/env python3
"""Plots docs/results/caustic_maps.csv (scripts/bench-caustic-maps.sh) into
caustic_maps.png: per scene, the relative L1 error against caustix-reference
over each caustic-map knob, with the light-transport tables' error as a
line, and the caustic maps' GPU time (capture + photons + splat) beside it."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

folder = sys.argv[1] if len(sys.argv) > 1 else "docs/results"
rows = list(csv.DictReader(open(os.path.join(folder, "caustic_maps.csv"))))
scenes = list(dict.fromkeys(r["scene"] for r in rows))
knobs = ["photons", "map_size", "sigma", "iterations"]
fig, axes = plt.subplots(len(scenes), len(knobs), figsize=(4 * len(knobs), 3.2 * len(scenes)), squeeze=False)
for i, s in enumerate(scenes):
    mine = [r for r in rows if r["scene"] == s]
    table = [r for r in mine if r["glass_method"] == "table"]
    default = [r for r in mine if r["glass_method"] == "caustic-map" and r["knob"] == "default"][0]
    for j, k in enumerate(knobs):
        ax = axes[i][j]
        pts = [r for r in mine if r["knob"] == k] + [default]
        dv = {"photons": 512, "map_size": 512, "sigma": 1, "iterations": 10}[k]
        xs = [float(r["value"]) if r["knob"] == k else dv for r in pts]
        order = sorted(range(len(xs)), key=lambda n: xs[n])
        xs = [xs[n] for n in order]
        err = [100 * float(pts[n]["rel_l1"]) for n in order]
        ms = [sum(float(pts[n][c] or 0) for c in ("capture_ms", "photon_ms", "splat_ms")) for n in order]
        ax.plot(xs, err, "o-", color="C0", label="caustic map: rel. L1 %")
        if table:
            ax.axhline(100 * float(table[0]["rel_l1"]), color="C2", ls="--", label="tables (default): rel. L1 %")
        ax.set_xlabel(k)
        ax.set_ylabel("relative L1 vs reference, %")
        if k in ("photons", "map_size"):
            ax.set_xscale("log", base=2)
        ax2 = ax.twinx()
        ax2.plot(xs, ms, "s:", color="C3", label="GPU ms (caustic map passes)")
        ax2.set_ylabel("ms (llvmpipe)")
        ax.set_title(s)
        if i == 0 and j == 0:
            h1, l1 = ax.get_legend_handles_labels()
            h2, l2 = ax2.get_legend_handles_labels()
            ax.legend(h1 + h2, l1 + l2, fontsize=7)
fig.tight_layout()
fig.savefig(os.path.join(folder, "caustic_maps.png"), dpi=90)
