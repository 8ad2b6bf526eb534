#!/usr/bin/python3
"""The default slope with and without strain softening at two mesh sizes (docs/water.md).

    /usr/bin/python3 bench/plot_softening_runout.py --runs DIR --out docs/images/softening_runout.png

DIR holds peak_H and soft_H folders of `talus run geometries/slope.toml --set mesh.size=H` (soft:
with the softening keys of docs/water.md), each with results.h5 and metrics.json.
"""
import argparse
import json
import os

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", required=True)
    parser.add_argument("--out", required=True)
    parser.add_argument("--sizes", default="0.5,0.25")
    args = parser.parse_args()
    sizes = args.sizes.split(",")
    fig, axes = plt.subplots(len(sizes), 1, figsize=(9, 3.2 * len(sizes)), sharex=True)
    for ax, size in zip(axes, sizes):
        for kind, colour, label in (("peak", "0.6", "peak strength only"),
                                    ("soft", "tab:red", "softening to phi_r = 20 deg, c_r = 0")):
            folder = os.path.join(args.runs, "%s_%s" % (kind, size))
            with h5py.File(os.path.join(folder, "results.h5"), "r") as f:
                x = f["frames/position"][-1]
                x0 = f["particles/initial_position"][...]
            with open(os.path.join(folder, "metrics.json")) as handle:
                runout = json.load(handle)["runout_distance_m"]
            ax.scatter(x[:, 0], x[:, 1], s=2, c=colour, linewidths=0,
                       label="%s: runout %.2f m" % (label, runout))
        ax.scatter(x0[:, 0], x0[:, 1], s=0.3, c="k", alpha=0.15, linewidths=0, label="initial")
        ax.set_aspect("equal")
        ax.set_ylabel("y (m)")
        ax.set_title("mesh.size = %s m" % size)
        ax.legend(loc="upper right", fontsize=8, markerscale=4)
    axes[-1].set_xlabel("x (m)")
    fig.savefig(args.out, dpi=130, bbox_inches="tight")
    print("wrote", args.out)


if __name__ == "__main__":
    main()
