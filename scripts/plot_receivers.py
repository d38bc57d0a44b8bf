#!/usr/bin/env python3
"""Plot of scripts/bench-receivers.sh's CSVs (docs/embedding.md, "Deferred
and multi-light renderers"): receivers.png, ms of lighting every receiver
from 3 lights per scene, the per-pair forward path against the deferred
pass over Engine::bind_all(), on llvmpipe (640 x 480) and on the H200
(1920 x 1080); each renderer's bars come from one run."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

out = sys.argv[1] if len(sys.argv) > 1 else "docs/results"
panels = [("receivers_llvmpipe.csv", "llvmpipe (2 cores)"), ("receivers_h200.csv", "NVIDIA H200 (headless EGL)")]
fig, axes = plt.subplots(1, len(panels), figsize=(11, 4))
for ax, (name, title) in zip(axes, panels):
    rows = list(csv.DictReader(open(os.path.join(out, name))))
    x = range(len(rows))
    ax.bar([i - 0.2 for i in x], [float(r["per_pair_ms"]) for r in rows], 0.4, label="per pair: bind() + a draw per (receiver, light)")
    ax.bar([i + 0.2 for i in x], [float(r["deferred_ms"]) for r in rows], 0.4, label="deferred: bind_all() + one full-screen pass")
    ax.set_xticks(list(x))
    ax.set_xticklabels([f'{r["label"]}\n{r["receivers"]} recv x {r["lights"]} lights' for r in rows], fontsize=7)
    ax.set_ylabel("ms (median)")
    ax.set_title(f"{title}, {rows[0]['size']}", fontsize=9)
    ax.legend(fontsize=7)
fig.tight_layout()
fig.savefig(os.path.join(out, "receivers.png"), dpi=110)
