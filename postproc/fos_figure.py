#!/usr/bin/python3
"""The figure of `talus fos`: OUT/fos.png from OUT/fos.json and OUT/fos_particles.csv.

Left: the slope in its initial configuration, particles coloured by their displacement in the
smallest failing trial, with the slip surface extracted from it, its fitted circle, and Bishop's
critical circle. Right: the monitoring point's displacement at each trial's verdict against F.

    /usr/bin/python3 postproc/fos_figure.py --out out/griffiths_lane
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def outline_top(outlines, x):
    """Height of the outlines' highest edge over each x (NaN outside them): the ground surface."""
    edges = []
    for outline in outlines:
        pts = np.array(outline)
        edges += list(zip(pts, np.roll(pts, -1, axis=0)))
    top = np.full(len(x), np.nan)
    for (x0, y0), (x1, y1) in edges:
        if x1 == x0:
            continue
        t = (x - x0) / (x1 - x0)
        inside = (t >= 0) & (t <= 1)
        y = y0 + t * (y1 - y0)
        top = np.where(inside & ~(y <= top), np.where(inside, y, top), top)
    return top


def arc_inside(circle, outlines, samples=721):
    """Points of the circle's lower half under the ground surface (the slip arc)."""
    theta = np.linspace(np.pi, 2 * np.pi, samples)
    x = circle["xc_m"] + circle["r_m"] * np.cos(theta)
    y = circle["yc_m"] + circle["r_m"] * np.sin(theta)
    keep = y <= outline_top(outlines, x) + 1e-9
    return np.where(keep, x, np.nan), np.where(keep, y, np.nan)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="folder with fos.json; fos.png is written there")
    args = parser.parse_args()
    with open(os.path.join(args.out, "fos.json")) as f:
        fos = json.load(f)

    fig, (ax, bx) = plt.subplots(1, 2, figsize=(13, 4.8), gridspec_kw={"width_ratios": [1.7, 1]})

    outlines = fos.get("body_outlines") or [fos["body_outline"]]
    for points in outlines:
        outline = np.array(points + [points[0]])
        ax.plot(outline[:, 0], outline[:, 1], color="0.3", lw=1)
    particles = os.path.join(args.out, "fos_particles.csv")
    if os.path.exists(particles):
        data = np.loadtxt(particles, delimiter=",", skiprows=1, ndmin=2)
        sc = ax.scatter(data[:, 0], data[:, 1], c=data[:, 2], s=3, cmap="viridis", rasterized=True)
        fig.colorbar(sc, ax=ax, shrink=0.8, label=f"displacement at F = {fos['failing_factor']:.3f} (m)")
    if fos.get("slip_surface"):
        line = np.array(fos["slip_surface"])
        ax.plot(line[:, 0], line[:, 1], color="crimson", lw=2.2, label="MPM slip surface (first failing F)")
    if fos.get("slip_circle"):
        x, y = arc_inside(fos["slip_circle"], outlines)
        ax.plot(x, y, color="crimson", lw=1, ls="--", label="circle fitted to it")
    if fos.get("bishop_circle"):
        x, y = arc_inside(fos["bishop_circle"], outlines)
        ax.plot(x, y, color="darkorange", lw=1.8, ls=":", label=f"Bishop critical circle, F = {fos['bishop_fos']:.3f}")
    m = fos["monitoring_point"]
    ax.plot([m["x_m"]], [m["y_m"]], marker="*", ms=12, color="k", ls="none", label="monitoring point")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"{fos['scene']}: F = {fos['factor_of_safety']:.3f} by strength reduction")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.25), ncol=2, fontsize=8)

    trials = fos["trials"]
    for failed, marker, colour, label in ((False, "o", "tab:green", "stable"), (True, "x", "tab:red", "failed")):
        f = [t["factor"] for t in trials if t["failed"] == failed]
        d = [t["monitor_displacement_m"] for t in trials if t["failed"] == failed]
        bx.plot(f, d, marker=marker, ls="none", color=colour, label=label)
    lo, hi = fos["bracket"]["lower"], fos["bracket"]["upper"]
    bx.axvspan(lo, hi, color="0.85", label=f"bracket [{lo:.3f}, {hi:.3f}]")
    if fos.get("bishop_fos"):
        bx.axvline(fos["bishop_fos"], color="darkorange", ls=":", label="Bishop")
    bx.axhline(fos["tolerances"]["displacement_limit_m"], color="0.4", ls="--", lw=1, label="displacement limit")
    bx.set_yscale("log")
    bx.set_xlabel("trial factor F")
    bx.set_ylabel("monitoring-point displacement from equilibrium (m)")
    bx.legend(fontsize=8)
    bx.grid(alpha=0.3)

    fig.tight_layout()
    path = os.path.join(args.out, "fos.png")
    fig.savefig(path + ".tmp.png", dpi=130)
    os.replace(path + ".tmp.png", path)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
