"""docs/results/glass_focus_encircled.png from glass_focus_encircled.csv.

The CSV holds glass_ball's power within r of the axis (m^2 E0), every
column over the same 0.5 mm pixels (+-5.1 cm, 204^2): the exact sphere
(tests/optics_oracle.h's landing_image and power_within), caustix-render
--irradiance floor at the defaults with and without --glass-no-focus, and
caustix-reference on sphere_fine.obj (40 M photons).
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

folder = sys.argv[1] if len(sys.argv) > 1 else "docs/results"
rows = list(csv.DictReader(open(f"{folder}/glass_focus_encircled.csv")))
r = [float(x["radius_mm"]) for x in rows]
cols = [("optics", "exact sphere (optics)", "k-"), ("reference_sphere_fine", "caustix-reference, fine sphere", "g--"),
        ("runtime_window", "runtime, focus window (default)", "b-"), ("runtime_no_window", "runtime, no window", "r-")]
fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4))
for key, label, style in cols:
    v = [float(x[key]) for x in rows]
    a.plot(r, v, style, label=label)
    if key != "optics":
        b.plot(r, [100 * (y / float(x["optics"]) - 1) for y, x in zip(v, rows)], style, label=label)
a.set_xlabel("radius (mm)")
a.set_ylabel("power within the radius (m² E0)")
a.set_title("glass_ball: light around the focus")
a.legend(fontsize=8)
b.axhline(0, color="k", lw=0.5)
b.set_xlabel("radius (mm)")
b.set_ylabel("against optics (%)")
b.set_ylim(-70, 10)
b.set_title("error of the encircled power")
fig.tight_layout()
fig.savefig(f"{folder}/glass_focus_encircled.png", dpi=90)
