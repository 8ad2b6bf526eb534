#!/usr/bin/python3
"""The figure of `talus converge`: OUT/converge.png from OUT/converge.csv.

One panel per metric: its value at each element size h (the study's levels), Richardson's
extrapolate at h = 0 where the convergence is monotone, and the grid convergence index as an
error bar on the finest level (the band of docs/converge.md).

    /usr/bin/python3 postproc/converge_figure.py OUT/converge.csv OUT/converge.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(text):
    return float(text) if text not in ("", None) else None


def main(csv_path, png_path):
    with open(csv_path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit(f"{csv_path}: no metric to draw")
    sizes = [k for k in rows[0] if k.startswith("h=")]
    h = [float(k[2:]) for k in sizes]
    n = len(rows)
    cols = min(n, 3)
    lines = (n + cols - 1) // cols
    fig, axes = plt.subplots(lines, cols, figsize=(4.2 * cols, 3.4 * lines), squeeze=False)
    for ax, row in zip(axes.flat, rows):
        values = [number(row[k]) for k in sizes]
        pairs = [(x, y) for x, y in zip(h, values) if y is not None]
        ax.plot([p[0] for p in pairs], [p[1] for p in pairs], "o-", color="C0", label="levels")
        band = number(row["gci"])
        fine = pairs[-1] if pairs else None
        if band is not None and fine is not None:
            ax.errorbar([fine[0]], [fine[1]], yerr=[band], fmt="none", ecolor="C3", capsize=5,
                        label=f"GCI band ({row['convergence']})")
        extrapolated = number(row["extrapolated"])
        if extrapolated is not None:
            ax.plot([0.0], [extrapolated], "s", color="C2", label="Richardson extrapolate")
            ax.plot([0.0, fine[0]], [extrapolated, fine[1]], ":", color="C2")
        ax.set_xlim(left=0)
        ax.set_xlabel("element size h (m)")
        ax.set_ylabel(f"{row['metric']} ({row['unit']})")
        ax.set_title(row["metric"])
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)
    print(f"wrote {png_path}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        raise SystemExit("usage: converge_figure.py CONVERGE.csv OUT.png")
    main(sys.argv[1], sys.argv[2])
