"""docs/results/fog_focus_axis.png from fog_focus_axis.csv.

The CSV holds fog_ball's in-scatter (scale 1/E0) in the 1 cm column on the
axis, 1 cm rows from the ball's bottom (y 0.75 m) to the floor: exact
optics (tests/media_oracle.h's fog_ball_column), the runtime at the
defaults with and without its focus grid, by the curved paths through the
blurred index (VolumeOptions::surface_refraction off), and
caustix-reference (1.5 M photons). Written by the test Volume.FogBallFocalLineAgreesWithOptics with
CAUSTIX_FOG_AXIS_CSV set.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

folder = sys.argv[1] if len(sys.argv) > 1 else "docs/results"
rows = list(csv.DictReader(open(f"{folder}/fog_focus_axis.csv")))
y = [float(x["y_m"]) for x in rows]
cols = [("optics", "exact sphere (optics)", "k-"), ("reference", "caustix-reference", "g--"),
        ("runtime_focus_grid", "runtime, focus grid, refraction at the surface (default)", "b-"), ("runtime_no_focus_grid", "runtime, no focus grid", "r-"),
        ("runtime_curved_paths", "runtime, curved paths", "m:")]
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
for key, label, style in cols:
    v = [float(x[key]) for x in rows]
    a.plot(y, v, style, label=label)
    if key != "optics":
        b.plot(y, [100 * (p / float(x["optics"]) - 1) for p, x in zip(v, rows)], style, label=label)
a.set_xlabel("height y (m); the ball's bottom at 0.75")
a.set_ylabel("in-scatter / E0, 1 cm column on the axis")
a.set_title("fog_ball: the focal line")
a.legend(fontsize=8)
b.axhline(0, color="k", lw=0.5)
b.set_xlabel("height y (m)")
b.set_ylabel("against optics (%)")
b.set_ylim(-70, 50)
b.set_title("error along the axis")
fig.tight_layout()
fig.savefig(f"{folder}/fog_focus_axis.png", dpi=90)
