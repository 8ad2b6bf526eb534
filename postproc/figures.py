#!/usr/bin/python3
"""Figures of a Talus run, drawn from results.h5 and the metrics.json that `talus post` wrote.

    /usr/bin/python3 postproc/figures.py --results out/slope/results.h5 --out out/slope

Writes into --out, according to what metrics.json holds:
  deformed.png     final particles coloured by displacement magnitude, with the initial outlines,
                   the slip surface, its fitted circle, the Bishop critical circle, the shear band,
                   and the water table at the start and at the end (scenes with [water])
  pore_pressure.png  final particles coloured by pore pressure, with the water table ([water] only)
  front.png        deposit front position and velocity over time   (metric "runout")
  energy.png       kinetic, strain and change of potential energy   (always)
  spring_mass.png  MPM settlement against A (1 - cos(omega t))      (metric "spring_mass")
  box_incline.png  MPM displacement along the slope against a t^2/2 (metric "box_incline")
  newmark_block.png  the shaken box's displacement against Newmark's block (metric "newmark_block")
and with --animate (the scene's post.animate), by animation.py:
  runout.mp4, runout.gif  the particles coloured by displacement over the saved frames
"""
import argparse
import csv
import json
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.patches import Circle  # noqa: E402
from mpl_toolkits.axes_grid1 import make_axes_locatable  # noqa: E402


def read_csv(path):
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    header, body = rows[0], np.array(rows[1:], dtype=float).reshape(-1, len(rows[0]))
    return {name: body[:, k] for k, name in enumerate(header)}


def save(fig, out, name, written):
    # Written beside and renamed, like fos.png: a failed write (a full disk) leaves no
    # truncated PNG under the final name.
    path = os.path.join(out, name)
    temporary = path + ".tmp.png"
    try:
        fig.savefig(temporary, dpi=150, bbox_inches="tight")
        os.replace(temporary, path)
    except BaseException:
        if os.path.exists(temporary):
            os.remove(temporary)
        raise
    finally:
        plt.close(fig)
    written.append(path)


def water_tables(results):
    """The water table at the first and the last frame, [(label, xy)], [] without [water]."""
    with h5py.File(results, "r") as f:
        if "settings/water" not in f:
            return []
        table = f["settings/water/table"][...].reshape(-1, 2)
        rise = f["settings/water/rise"][...].reshape(-1, 2)
        times = f["frames/time"][...]
    tables = []
    for label, t in (("water table at t = %.2f s", times[0] if len(times) else 0.0),
                     ("water table at t = %.2f s", times[-1] if len(times) else 0.0)):
        dh = np.interp(t, rise[:, 0], rise[:, 1]) if len(rise) else 0.0
        tables.append((label % t, table + np.array([0.0, dh])))
    if len(rise) == 0 or np.allclose(tables[0][1], tables[1][1]):
        tables = [("water table", table)]
    return tables


def scene_axes(ax, lo, hi):
    """Equal-aspect axes in metres over the box [lo, hi], padded by 5 % of its larger side."""
    pad = 0.05 * (hi - lo).max()
    ax.set_xlim(lo[0] - pad, hi[0] + pad)
    ax.set_ylim(lo[1] - pad, hi[1] + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")


def draw_water(ax, tables, lo, hi):
    for k, (label, xy) in enumerate(tables):
        # Held level beyond its ends, as the solver reads it.
        xs = np.concatenate([[min(lo[0], xy[0, 0])], xy[:, 0], [max(hi[0], xy[-1, 0])]])
        ys = np.concatenate([[xy[0, 1]], xy[:, 1], [xy[-1, 1]]])
        ax.plot(xs, ys, color="tab:blue", ls=":" if k == 0 and len(tables) > 1 else "-", lw=1.4, label=label)


def pore_pressure(results, metrics, out, written):
    with h5py.File(results, "r") as f:
        if "frames/pore_pressure" not in f:
            return
        x1 = f["frames/position"][-1]
        u = f["frames/pore_pressure"][-1]
        volume = f["particles/volume"][...]
        time = f["frames/time"][-1]
    fig, ax = plt.subplots(figsize=(10, 5))
    span = max(np.ptp(x1, axis=0)[0], 1e-9)
    marker = max((np.sqrt(np.median(volume)) * 8.5 * 72 / span) ** 2, 0.3)
    points = ax.scatter(x1[:, 0], x1[:, 1], c=u / 1e3, s=marker, cmap="Blues", linewidths=0)
    fig.colorbar(points, cax=make_axes_locatable(ax).append_axes("right", size="2.5%", pad=0.1),
                 label="pore pressure (kPa, compression positive)")
    lo, hi = x1.min(axis=0), x1.max(axis=0)
    draw_water(ax, water_tables(results)[-1:], lo, hi)
    scene_axes(ax, lo, hi)
    ax.set_title("%s: pore pressure at t = %.2f s" % (metrics.get("scene", ""), time))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), fontsize=8, frameon=False)
    save(fig, out, "pore_pressure.png", written)


def deformed(results, metrics, out, written):
    with h5py.File(results, "r") as f:
        x0 = f["particles/initial_position"][...]
        volume = f["particles/volume"][...]
        x1 = f["frames/position"][-1]
        time = f["frames/time"][-1]
        names = [n.decode() if isinstance(n, bytes) else n for n in f["bodies/names"][...]]
        outlines = []
        for name in names:
            group = f["bodies/" + name]
            outlines += [group["loop_%d" % k][...] for k in range(int(group.attrs["loops"]))]
    displacement = np.linalg.norm(x1 - x0, axis=1)

    width_inches = 8.5
    fig, ax = plt.subplots(figsize=(width_inches + 1.5, 5))
    # Marker area (points^2) so that neighbouring particles just touch: spacing sqrt(volume).
    span = max(np.ptp(np.vstack([x1] + outlines), axis=0)[0], 1e-9)
    spacing_points = np.sqrt(np.median(volume)) * width_inches * 72 / span
    marker = max(spacing_points ** 2, 0.3)
    points = ax.scatter(x1[:, 0], x1[:, 1], c=displacement, s=marker, cmap="viridis", linewidths=0)
    colour_axes = make_axes_locatable(ax).append_axes("right", size="2.5%", pad=0.1)  # as tall as the plot
    fig.colorbar(points, cax=colour_axes, label="displacement magnitude (m)")
    for k, loop in enumerate(outlines):
        closed = np.vstack([loop, loop[:1]])
        ax.plot(closed[:, 0], closed[:, 1], "k--", lw=0.8, label="initial outline" if k == 0 else None)
    surface = np.array(metrics.get("failure_surface") or [])
    if len(surface):
        ax.plot(surface[:, 0], surface[:, 1], "r-", lw=1.8, label="slip surface (initial configuration)")
    band = np.array(metrics.get("shear_band") or [])
    if len(band):
        ax.plot(band[:, 0], band[:, 1], color="orange", ls=":", lw=1.8, label="shear band at onset")
    for key, colour, label in (("slip_circle", "r", "fitted circle"), ("bishop_circle", "b", "Bishop critical circle")):
        circle = metrics.get(key)
        if circle:
            if key == "bishop_circle" and metrics.get("bishop_fos") is not None:
                label += " (F = %.2f)" % metrics["bishop_fos"]
            ax.add_patch(Circle((circle["xc_m"], circle["yc_m"]), circle["r_m"], fill=False, ec=colour,
                                ls="-." if key == "slip_circle" else "--", lw=1.0, label=label))
    tip = metrics.get("deposit_tip_m")
    if tip and metrics.get("deposit_found"):
        ax.plot(*tip, "kv", ms=7, label="deposit tip (runout %.2f m)" % metrics["runout_distance_m"])
    # The view is the material, not the circles (whose centres lie far above the slope).
    everything = np.vstack([x1] + outlines)
    lo, hi = everything.min(axis=0), everything.max(axis=0)
    draw_water(ax, water_tables(results), lo, hi)
    scene_axes(ax, lo, hi)
    ax.set_title("%s: total displacement at t = %.2f s" % (metrics.get("scene", ""), time))
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=3, fontsize=8, frameon=False)
    save(fig, out, "deformed.png", written)


def front(out, written):
    data = read_csv(os.path.join(out, "front.csv"))
    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
    top.plot(data["time_s"], data["front_x_m"], "k.-")
    top.set_ylabel("front position x (m)")
    bottom.plot(data["time_s"], data["front_velocity_m_s"], "r.-")
    bottom.set_ylabel("front velocity (m/s)")
    bottom.set_xlabel("time (s)")
    top.set_title("deposit front")
    for ax in (top, bottom):
        ax.grid(alpha=0.3)
    save(fig, out, "front.png", written)


def energy(out, written):
    data = read_csv(os.path.join(out, "energy.csv"))
    if len(data["time_s"]) == 0:
        return
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(data["time_s"], data["kinetic_J"], label="kinetic")
    ax.plot(data["time_s"], data["strain_J"], label="strain")
    ax.plot(data["time_s"], data["potential_J"] - data["potential_J"][0], label="potential - initial")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("energy (J per m thickness)")
    ax.grid(alpha=0.3)
    ax.legend(loc="best")
    ax.set_title("energy history")
    save(fig, out, "energy.png", written)


def comparison(out, name, ylabel, title, written, reference="analytical"):
    data = read_csv(os.path.join(out, name + ".csv"))
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(data["time_s"], data["exact_m"], "k-", label=reference)
    ax.plot(data["time_s"], data["mpm_m"], "o", ms=3, mfc="none", label="MPM")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    ax.legend()
    ax.set_title(title)
    save(fig, out, name + ".png", written)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--results", required=True, help="results.h5 of the run")
    parser.add_argument("--out", required=True, help="folder holding metrics.json; figures go there")
    parser.add_argument("--animate", action="store_true", help="also write runout.mp4 and runout.gif (ffmpeg)")
    args = parser.parse_args()
    with open(os.path.join(args.out, "metrics.json")) as handle:
        metrics = json.load(handle)
    asked = set(metrics.get("metrics", []))
    written = []
    if asked & {"runout", "failure_surface", "bishop"} or not asked & {"spring_mass", "box_incline", "newmark_block"}:
        deformed(args.results, metrics, args.out, written)
        pore_pressure(args.results, metrics, args.out, written)
    if "runout" in asked:
        front(args.out, written)
    energy(args.out, written)
    if "spring_mass" in asked:
        s = metrics["spring_mass"]
        comparison(args.out, "spring_mass", "settlement of the mass (m)",
                   "spring and mass: max error / A = %.3f" % s["max_error_over_amplitude"], written)
    if "box_incline" in asked:
        b = metrics["box_incline"]
        comparison(args.out, "box_incline", "displacement along the slope (m)",
                   "box on a %.0f deg incline, mu = %.2f" % (b["angle_deg"], b["friction"]), written)
    if "newmark_block" in asked:
        b = metrics["newmark_block"]
        comparison(args.out, "newmark_block", "down the incline, from the ground (m)",
                   "shaken box, mu = %.2f: MPM %.4f m, Newmark %.4f m" % (
                       b["friction"], b["mpm_displacement_m"], b["newmark_displacement_m"]),
                   written, reference="Newmark (1965) rigid block")
    if args.animate:
        import animation
        front_csv = os.path.join(args.out, "front.csv")
        front_data = read_csv(front_csv) if "runout" in asked and os.path.exists(front_csv) else None
        animation.animate(args.results, metrics, args.out, written, front_data)
    for path in written:
        print("wrote", path)


if __name__ == "__main__":
    sys.exit(main())
