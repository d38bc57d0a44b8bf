#!/usr/bin/python3
"""Plots for docs/level-maps.md from the CSVs caustix-bench writes."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# Tipprasert 2006, table 5-4 (teapot, dolphin, sphere), specified 3..28 planes.
THESIS = {
    "teapot": [2, 3, 3, 4, 5, 5, 5, 6, 7, 7, 8, 8, 9, 9, 10, 11, 11, 11, 12, 13, 13, 14, 15, 16, 16, 17],
    "dolphin": [2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23, 24, 25, 26, 27],
    "sphere": [1, 2, 2, 3, 3, 4, 4, 5, 6, 6, 6, 7, 7, 8, 8, 9, 10, 10, 11, 11, 11, 12, 12, 13, 13, 14],
}


def main(folder):
    rows = list(csv.DictReader(open(f"{folder}/table_5_4.csv")))
    n = [int(r["specified"]) for r in rows]
    fig, ax = plt.subplots(figsize=(7, 4.5))
    ax.plot(n, [int(r["uniform_planes"]) for r in rows], "k--", label="uniform (n + 1 planes)")
    for model, colour in (("sphere", "tab:blue"), ("teapot", "tab:orange"), ("organic", "tab:green")):
        ax.plot(n, [int(r[model]) for r in rows], "-o", color=colour, ms=3, label=f"caustix smart: {model}")
    for model, colour in (("sphere", "tab:blue"), ("teapot", "tab:orange"), ("dolphin", "tab:green")):
        ax.plot(n, THESIS[model], ":", color=colour, label=f"thesis table 5-4: {model}")
    ax.set_xlabel("specified planes n")
    ax.set_ylabel("planes drawn")
    ax.set_title("Smart slicing: planes actually needed (Tipprasert 2006 table 5-4)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(f"{folder}/table_5_4.png", dpi=110)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "docs/results")
