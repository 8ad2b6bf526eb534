#!/usr/bin/python3
"""The figures of `talus ensemble` (docs/ensemble.md), from OUT/ensemble.json,
OUT/realisations.csv and OUT/fields.csv:

    ensemble_exceedance.png  P(runout > r) with its pointwise 95 % Wilson band
    ensemble_reach.png       along the ground, the probability that the failure reaches each
                             point, over the slope's outline
    ensemble_running.png     the running estimate of the probability of failure against the
                             number of realisations (seed order), with its 95 % Wilson band
    ensemble_fields.png      the first two realisations' fields at the particles

    /usr/bin/python3 postproc/ensemble_figure.py --out out/slope_random/ensemble
"""
import argparse
import csv
import json
import math
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

Z95 = 1.959963984540054


def wilson(k, n):
    """The 95 % Wilson score interval of k successes in n trials (as the C++ statistics)."""
    p = k / n
    d = 1 + Z95**2 / n
    centre = (p + Z95**2 / (2 * n)) / d
    half = Z95 * math.sqrt(p * (1 - p) / n + Z95**2 / (4 * n * n)) / d
    return max(0.0, centre - half), min(1.0, centre + half)


def read_rows(path):
    with open(path) as f:
        lines = [line for line in f if not line.startswith("#")]
    return [r for r in csv.DictReader(lines) if r["solved"] == "1"]


def exceedance_figure(summary, out):
    e = summary["exceedance"]
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    ax.fill_between(e["runout_m"], e["lower_95"], e["upper_95"], step="post", color="tab:blue", alpha=0.25,
                    label="95 % Wilson band (pointwise)")
    ax.step(e["runout_m"], e["probability"], where="post", color="tab:blue", label="P(runout > r)")
    q = summary["runout_quantiles_m"]
    for name, ls in (("P50", ":"), ("P90", "--"), ("P95", "-.")):
        ax.axvline(q[name], color="0.4", ls=ls, lw=0.9, label=f"{name} = {q[name]:.2f} m")
    ax.set_xlabel("runout r from the initial toe (m)")
    ax.set_ylabel("probability of exceedance")
    ax.set_ylim(0, 1.02)
    ax.set_title(f"{summary['scene']}: {summary['solved']} realisations, "
                 f"P_f = {summary['probability_of_failure']:.2f}")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "ensemble_exceedance.png"), dpi=130)
    plt.close(fig)


def reach_figure(summary, out):
    r = summary["reach"]
    ground = np.array(summary["ground_surface"])
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.2, 5.4), sharex=True,
                                      gridspec_kw={"height_ratios": [1, 1.3]})
    top.fill_between(r["x_m"], r["lower_95"], r["upper_95"], color="tab:red", alpha=0.25, label="95 % Wilson band")
    top.plot(r["x_m"], r["probability"], color="tab:red", label="P(failure reaches x)")
    top.set_ylabel("probability")
    top.set_ylim(0, 1.02)
    top.legend(fontsize=8)
    x = np.array(r["x_m"])
    y = np.array(r["ground_y_m"])
    p = np.array(r["probability"])
    base = min(ground[:, 1].min(), y.min())
    bottom.fill_between(ground[:, 0], base, ground[:, 1], color="0.85", label="slope (initial)")
    points = bottom.scatter(x, y, c=p, cmap="Reds", vmin=0, vmax=1, s=14, zorder=3)
    fig.colorbar(points, ax=[top, bottom], label="P(reached)")  # on both, so that their x scales match
    bottom.plot(*summary["toe_m"], "kv", label="toe")
    bottom.set_xlabel("x (m)")
    bottom.set_ylabel("y (m)")
    bottom.legend(fontsize=8, loc="upper right")
    top.set_title("reach: the ground between the failure's crown and the deposit's tip")
    fig.savefig(os.path.join(out, "ensemble_reach.png"), dpi=130)
    plt.close(fig)


def running_figure(rows, out):
    failed = np.array([int(r["failed"]) for r in rows])
    n = np.arange(1, len(failed) + 1)
    k = np.cumsum(failed)
    band = np.array([wilson(int(a), int(b)) for a, b in zip(k, n)])
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    ax.fill_between(n, band[:, 0], band[:, 1], color="tab:green", alpha=0.25, label="95 % Wilson interval")
    ax.plot(n, k / n, color="tab:green", label="P_f after n realisations")
    ax.set_xlabel("realisations n (seed order)")
    ax.set_ylabel("probability of failure")
    ax.set_ylim(0, 1.02)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "ensemble_running.png"), dpi=130)
    plt.close(fig)


def fields_figure(out):
    with open(os.path.join(out, "fields.csv")) as f:
        table = list(csv.DictReader(f))
    names = [c for c in table[0] if c not in ("x_m", "y_m")]
    fields = sorted({c.split("@")[0] for c in names}, key=[c.split("@")[0] for c in names].index)
    seeds = sorted({c.split("@")[1] for c in names}, key=[c.split("@")[1] for c in names].index)
    x = np.array([float(r["x_m"]) for r in table])
    y = np.array([float(r["y_m"]) for r in table])
    fig, axes = plt.subplots(len(fields), len(seeds), figsize=(4.2 * len(seeds) + 0.6, 2.3 * len(fields) + 0.4),
                             squeeze=False)
    for i, field in enumerate(fields):
        values = {s: np.array([float(r[field + "@" + s]) for r in table]) for s in seeds}
        lo = min(v.min() for v in values.values())
        hi = max(v.max() for v in values.values())
        for j, seed in enumerate(seeds):
            ax = axes[i, j]
            dots = ax.scatter(x, y, c=values[seed], s=3, cmap="viridis", vmin=lo, vmax=hi)
            ax.set_title(f"{field}, {seed.replace('seed', 'seed ')}", fontsize=9)
            ax.set_aspect("equal")
        fig.colorbar(dots, ax=list(axes[i, :]), label=field.split(".")[-1])
    fig.savefig(os.path.join(out, "ensemble_fields.png"), dpi=130)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    with open(os.path.join(args.out, "ensemble.json")) as f:
        summary = json.load(f)
    rows = read_rows(os.path.join(args.out, "realisations.csv"))
    if summary.get("solved", 0) > 0:
        exceedance_figure(summary, args.out)
        reach_figure(summary, args.out)
        running_figure(rows, args.out)
    fields_figure(args.out)
    print("wrote the figures ensemble_*.png in " + args.out)


if __name__ == "__main__":
    main()
