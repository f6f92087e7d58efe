"""Plots an ivgi sweep: error against time per frame, one point per setting, each series' Pareto front
joined (iv with every surfel a receiver and iv with adaptive receivers are two series).

Usage: python3 plot_sweep.py SWEEP.csv PLOT.png [--metric relMSE|FLIP]
Run by `ivgi sweep` (the script is compiled into the binary); needs python3-matplotlib.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def series(row):
    """iv's points split by how its receivers are chosen; other methods by name."""
    if row["method"] != "iv" or "receiverTol" not in row:
        return row["method"]
    return "iv, every surfel" if float(row["receiverTol"]) == 0 else "iv, adaptive receivers"


def main(argv):
    source, target = argv[1], argv[2]
    metric = argv[4] if len(argv) > 4 and argv[3] == "--metric" else "relMSE"
    with open(source, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{source}: no settings to plot")
    fig, ax = plt.subplots(figsize=(7.5, 5), dpi=120)
    for name in sorted({series(r) for r in rows}):
        pts = sorted((r for r in rows if series(r) == name), key=lambda r: (float(r["ms"]), float(r[metric])))
        dots = ax.scatter([float(r["ms"]) for r in pts], [float(r[metric]) for r in pts], s=22, alpha=0.7, label=name)
        front, best = [], float("inf")
        for r in pts:
            if float(r[metric]) < best:
                front.append(r)
                best = float(r[metric])
        ax.plot([float(r["ms"]) for r in front], [float(r[metric]) for r in front], "-", lw=1.2,
                color=dots.get_facecolor()[0])
    for r in rows:
        if r["pareto"] == "1":
            ax.annotate(r["label"], (float(r["ms"]), float(r[metric])), fontsize=7, xytext=(4, 3),
                        textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("GPU ms per frame (median)")
    ax.set_ylabel(f"{metric} against the reference")
    ax.set_title(rows[0]["scene"] + ": speed against accuracy (lines: each series' Pareto front)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(target)


if __name__ == "__main__":
    main(sys.argv)
