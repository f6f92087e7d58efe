"""Plots an ivgi sweep: error against time per frame, one point per setting, the Pareto front joined.

Usage: python3 plot_sweep.py SWEEP.csv PLOT.png [--metric relMSE|FLIP]
Run by `ivgi sweep` (the script is compiled into the binary); needs python3-matplotlib.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(argv):
    source, target = argv[1], argv[2]
    metric = argv[4] if len(argv) > 4 and argv[3] == "--metric" else "relMSE"
    with open(source, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{source}: no settings to plot")
    fig, ax = plt.subplots(figsize=(7.5, 5), dpi=120)
    for method in sorted({r["method"] for r in rows}):
        pts = [r for r in rows if r["method"] == method]
        ax.scatter([float(r["ms"]) for r in pts], [float(r[metric]) for r in pts], s=22, alpha=0.7, label=method)
    front = sorted((r for r in rows if r["pareto"] == "1"), key=lambda r: float(r["ms"]))
    ax.plot([float(r["ms"]) for r in front], [float(r[metric]) for r in front], "k-", lw=1.2, label="Pareto front")
    for r in front:
        ax.annotate(r["label"], (float(r["ms"]), float(r[metric])), fontsize=7, xytext=(4, 3), textcoords="offset points")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("GPU ms per frame (median)")
    ax.set_ylabel(f"{metric} against the reference")
    ax.set_title(rows[0]["scene"] + ": speed against accuracy")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(target)


if __name__ == "__main__":
    main(sys.argv)
