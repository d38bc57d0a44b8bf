"""docs/results/bake_rays.png from bake_rays.csv (scripts/bench-bake-rays.sh).

Per scene, side by side from one run on the same machine: the tables' rays
per second and the whole bake's seconds with CGAL's tree (--ltt-rays cgal),
with Embree as it was before its device stopped capping TBB at one thread
(embree_before, an older baker), and with Embree now (the default).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

folder = sys.argv[1] if len(sys.argv) > 1 else "docs/results"
rows = list(csv.DictReader(open(f"{folder}/bake_rays.csv")))
scenes = list(dict.fromkeys(r["scene"] for r in rows))
engines = [("cgal", "CGAL tree", "tab:gray"), ("embree_before", "Embree, one core (before)", "tab:orange"),
           ("embree", "Embree (now)", "tab:blue")]
fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.5))
width = 0.27
for k, (key, label, colour) in enumerate(engines):
    got = {r["scene"]: r for r in rows if r["rays_engine"] == key}
    xs = [i + (k - 1) * width for i, s in enumerate(scenes) if s in got]
    a.bar(xs, [float(got[s]["rays_per_s"]) / 1e6 for s in scenes if s in got], width, label=label, color=colour)
    b.bar(xs, [float(got[s]["bake_s"]) for s in scenes if s in got], width, label=label, color=colour)
for ax in (a, b):
    ax.set_xticks(range(len(scenes)))
    ax.set_xticklabels([s.replace("_", " ") for s in scenes], rotation=20, ha="right", fontsize=8)
a.set_ylabel("tables' rays per second (M)")
b.set_ylabel("whole bake (s)")
b.set_yscale("log")
a.set_title("light-transport tables: rays/s, 2 cores")
b.set_title("bake time (log scale), 2 cores")
a.set_ylim(0, 1.35 * max(float(r["rays_per_s"]) for r in rows) / 1e6)
a.legend(fontsize=8, loc="upper left", ncol=3)
fig.tight_layout()
fig.savefig(f"{folder}/bake_rays.png", dpi=110)
print(f"wrote {folder}/bake_rays.png")
