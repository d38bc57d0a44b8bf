#!/usr/bin/python3
"""Plots for docs/tradeoff.md from docs/results/tradeoff_<scene>.csv (caustix-bench tradeoff).

Per scene: relative L1 error against ms per frame for every setting, the Pareto
front (no other setting is both faster and more accurate) marked, the presets
labelled; and each knob's error against its value."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def pareto(points):
    """Indices of the points no other point beats in both time and error."""
    front = []
    for i, (t, e) in enumerate(points):
        if not any((t2 <= t and e2 <= e) and (t2 < t or e2 < e) for j, (t2, e2) in enumerate(points) if j != i):
            front.append(i)
    return sorted(front, key=lambda i: points[i][0])


def main(folder, scenes):
    for scene in scenes:
        rows = list(csv.DictReader(open(f"{folder}/tradeoff_{scene}.csv")))
        knobs = list(dict.fromkeys(r["knob"] for r in rows if r["knob"] != "preset"))
        fig, (front_ax, knob_ax) = plt.subplots(1, 2, figsize=(13, 5))
        cmap = plt.get_cmap("tab10")
        pts = [(float(r["frame_ms"]), float(r["rel_l1"])) for r in rows]
        for k, knob in enumerate(knobs):
            sel = [r for r in rows if r["knob"] == knob]
            front_ax.scatter([float(r["frame_ms"]) for r in sel], [float(r["rel_l1"]) for r in sel], s=18,
                             color=cmap(k % 10), label=knob)
            vals = [float(r["value"]) for r in sel]
            knob_ax.plot(range(len(vals)), [float(r["rel_l1"]) for r in sel], "-o", ms=3, color=cmap(k % 10),
                         label=f"{knob}: " + ", ".join(r["value"] for r in sel))
        presets = [r for r in rows if r["knob"] == "preset"]
        for r in presets:
            front_ax.scatter(float(r["frame_ms"]), float(r["rel_l1"]), marker="*", s=160, color="k", zorder=5)
            front_ax.annotate(r["value"], (float(r["frame_ms"]), float(r["rel_l1"])), textcoords="offset points",
                              xytext=(6, 6), fontsize=9)
        front = pareto(pts)
        front_ax.plot([pts[i][0] for i in front], [pts[i][1] for i in front], "k--", lw=1, label="Pareto front")
        noise = float(rows[0]["reference_noise"])
        front_ax.axhline(noise, color="grey", ls=":", label=f"reference noise {noise:.3f}")
        knob_ax.axhline(noise, color="grey", ls=":")
        front_ax.set_xscale("log")
        media = rows[0]["receiver"] == "(in-scatter)"  # scripts/bench-tradeoff.sh: media frames at 320x200
        front_ax.set_xlabel(f"ms per frame, {'320x200' if media else '640x480'} ({rows[0]['renderer'].split(',')[0]})")
        front_ax.set_ylabel(f"relative L1 error of {'in-scatter' if media else 'irradiance'} vs caustix-reference")
        front_ax.set_title(f"{scene}: error against frame time")
        front_ax.legend(fontsize=7, loc="upper right")
        knob_ax.set_xlabel("knob value, in sweep order (listed in the legend)")
        knob_ax.set_ylabel("relative L1 error")
        knob_ax.set_title(f"{scene}: one knob at a time from 'balanced'")
        knob_ax.legend(fontsize=6)
        for ax in (front_ax, knob_ax):
            ax.grid(alpha=0.3)
        fig.tight_layout()
        fig.savefig(f"{folder}/tradeoff_{scene}.png", dpi=100)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])
