"""docs/results/temporal.png from temporal_llvmpipe.csv (scripts/bench-temporal.sh).

Left: rho at half the step over rho at the step, per case and preset
(0.5: the change follows the motion smoothly; 1: per-frame noise or
snapping; the dashed line is the 0.7 target). Right: the largest jump a
frame at the step, of the focus power within 1 cm (glass_ball, fog_ball)
or of the brightest pixel (the pool). With a second CSV of the same cases
measured before a change (BEFORE), its values are drawn over the bars as
black ticks.

Usage: plot_temporal.py [CSV] [PNG] [BEFORE]
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

src = sys.argv[1] if len(sys.argv) > 1 else "docs/results/temporal_llvmpipe.csv"
dst = sys.argv[2] if len(sys.argv) > 2 else "docs/results/temporal.png"
rows = list(csv.DictReader(open(src)))
before = list(csv.DictReader(open(sys.argv[3]))) if len(sys.argv) > 3 else []


def case(r):
    scene = r["scene"].rsplit("_", 1)[0]
    if r["method"] == "media":
        return f"{scene}\nvolume"
    if scene == "glass_ball":
        return f"{scene}\n{r['glass_method']}"
    return f"{scene}\n{r['method']}"


presets = list(dict.fromkeys(r["label"] for r in rows))
cases = list(dict.fromkeys(case(r) for r in rows))
fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.2))
width = 0.8 / max(1, len(presets))
for k, preset in enumerate(presets):
    xs, ratio, jump = [], [], []
    for i, c in enumerate(cases):
        for r in rows:
            if r["label"] == preset and case(r) == c:
                xs.append(i + (k - (len(presets) - 1) / 2) * width)
                ratio.append(float(r["rho_ratio"]))
                focus = float(r["focus_jump_pct"])
                jump.append(focus if focus > 0 else float(r["peak_jump_pct"]))
    a.bar(xs, ratio, width, label=preset)
    b.bar(xs, jump, width, label=preset)
    # The same cases before, where measured.
    for i, c in enumerate(cases):
        for r in before:
            if r["label"] == preset and case(r) == c:
                x = i + (k - (len(presets) - 1) / 2) * width
                focus = float(r["focus_jump_pct"])
                a.plot([x - width / 2, x + width / 2], [float(r["rho_ratio"])] * 2, "k-", lw=2)
                b.plot([x - width / 2, x + width / 2], [focus if focus > 0 else float(r["peak_jump_pct"])] * 2, "k-", lw=2)
for ax in (a, b):
    ax.set_xticks(range(len(cases)))
    ax.set_xticklabels(cases, fontsize=8)
    ax.legend(fontsize=8)
a.axhline(0.7, color="k", ls="--", lw=1)
a.axhline(0.5, color="g", ls=":", lw=1)
a.axhline(1.0, color="r", ls=":", lw=1)
a.set_ylabel("rho at half the step / rho at the step")
a.set_title("smooth 0.5, noise 1 (target <= 0.7); black: before" if before else "smooth 0.5, noise 1 (target <= 0.7)")
b.set_ylabel("largest jump a frame at the step (%)")
b.set_title("focus power within 1 cm; the pool: brightest pixel")
fig.tight_layout()
fig.savefig(dst, dpi=110)
