"""Plots caustix-bench water-sim's grid sweep: ms per 60 Hz frame of the
interactive water's step against the grid's vertex count.
Usage: plot_water_sim.py CSV PNG"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

rows = [r for r in csv.DictReader(open(sys.argv[1])) if r["scene"] == "-"]
n = [int(r["grid"].split("x")[0]) for r in rows]
ms = [float(r["median_ms"]) for r in rows]
sub = [float(r["substeps_per_frame"]) for r in rows]
fig, ax = plt.subplots(figsize=(6, 4))
ax.loglog([k * k for k in n], ms, "o-", label="step of 1/60 s")
for k, m, s in zip(n, ms, sub):
    ax.annotate(f"{k}², {s:.0f} substep{'s' if s > 1 else ''}", (k * k, m), textcoords="offset points",
                xytext=(6, -12), fontsize=8)
ax.set_xlabel("grid vertices")
ax.set_ylabel("ms per 60 Hz frame")
ax.set_title(f"Interactive water (c = 0.6 m/s, 4 m pool)\n{rows[0]['renderer']}", fontsize=9)
ax.grid(True, which="both", alpha=0.3)
ax.legend()
fig.tight_layout()
fig.savefig(sys.argv[2], dpi=110)
