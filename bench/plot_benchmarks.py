"""Figures of the accuracy, stability and runout benchmarks, from the CSVs the C++ programs write.

    /usr/bin/python3 bench/plot_benchmarks.py accuracy OUT_DIR    bench_accuracy_*.png
    /usr/bin/python3 bench/plot_benchmarks.py stability OUT_DIR   bench_stability_energy.png
    /usr/bin/python3 bench/plot_benchmarks.py runout OUT_DIR      bench_runout_column.png, bench_runout_rods.png

Needs Debian's python3-matplotlib (hence /usr/bin/python3). A missing CSV is skipped.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402

SCENE_TITLES = {
    "spring_mass": "Spring and mass: max |y - y_exact| / A over two periods",
    "box_incline": "Box on incline: max relative error at t = 0.25 ... 1 s",
}
MARKERS = {1: "v", 3: "^", 4: "o", 6: "s", 10: "D"}


def read_csv(path):
    with open(path, newline="") as f:
        return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(f)]


def read_column_csv(path):
    """runout_column.csv: text columns stay text; the runout ratio may be empty (a failed run)."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    for row in rows:
        row["aspect_ratio"] = float(row["aspect_ratio"])
        row["runout_ratio"] = float(row["runout_ratio"]) if row["runout_ratio"] else ""
        post = row.get("post_runout_ratio") or ""  # absent in files written before it
        row["post_runout_ratio"] = float(post) if post else ""
        height = row.get("height_ratio") or ""  # absent in files written before it
        row["height_ratio"] = float(height) if height else ""
    return rows


def plot_error_against_time(rows, scene, path):
    fig, ax = plt.subplots(figsize=(7.5, 5))
    sizes = sorted({r["mesh_size_m"] for r in rows}, reverse=True)
    colours = plt.cm.viridis([i / max(1, len(sizes) - 1) * 0.85 for i in range(len(sizes))])
    for colour, size in zip(colours, sizes):
        for ppc in sorted({int(r["particles_per_cell"]) for r in rows}):
            sel = [r for r in rows if r["mesh_size_m"] == size and int(r["particles_per_cell"]) == ppc]
            if not sel:
                continue
            ax.scatter([r["wall_seconds"] for r in sel], [100 * r["error"] for r in sel],
                       color=colour, marker=MARKERS.get(ppc, "o"), s=[20 + 40 * r["cfl"] for r in sel],
                       alpha=0.8, edgecolors="none")
    front = sorted((r for r in rows if r["pareto"] == 1), key=lambda r: r["wall_seconds"])
    ax.plot([r["wall_seconds"] for r in front], [100 * r["error"] for r in front], "-", color="crimson",
            lw=1.5, zorder=0, label="Pareto front")
    ax.scatter([r["wall_seconds"] for r in front], [100 * r["error"] for r in front], facecolors="none",
               edgecolors="crimson", s=110, lw=1.2)
    ax.axhline(1.0, color="grey", ls="--", lw=1, label="1% error")
    ax.set_xscale("log")
    ax.set_yscale("log")
    plain = matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}")
    ax.yaxis.set_major_formatter(plain)
    ax.yaxis.set_minor_formatter(plain)
    threads = sorted({int(r["threads"]) for r in rows if "threads" in r})
    on = f"{threads[0]} thread{'s' if threads[0] > 1 else ''}" if len(threads) == 1 else "the sweep's --threads"
    ax.set_xlabel(f"wall time per run (s, meshing + solve, {on})")
    ax.set_ylabel("error (%)")
    ax.set_title(SCENE_TITLES.get(scene, scene), fontsize=10)
    # Legend: colour = element size, marker = particles per cell, marker size = CFL.
    handles = [plt.Line2D([], [], ls="", marker="o", color=c, label=f"h = {s:g} m") for c, s in zip(colours, sizes)]
    handles += [plt.Line2D([], [], ls="", marker=MARKERS.get(p, "o"), color="k", mfc="none", label=f"{p} per cell")
                for p in sorted({int(r["particles_per_cell"]) for r in rows})]
    handles += [plt.Line2D([], [], ls="", marker="o", color="k", ms=math.sqrt(20 + 40 * c), label=f"CFL {c:g}")
                for c in sorted({r["cfl"] for r in rows})]
    handles += ax.get_legend_handles_labels()[0]
    ax.legend(handles=handles, fontsize=7, loc="best", ncol=2)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_slope(rows, path):
    rows = sorted(rows, key=lambda r: r["mesh_size_m"])
    h = [r["mesh_size_m"] for r in rows]
    fig, (left, right) = plt.subplots(1, 2, figsize=(9, 4))
    left.plot(h, [r["runout_m"] for r in rows], "o-", label="runout")
    left.plot(h, [r["slip_circle_r_m"] for r in rows], "s-", label="slip circle radius")
    left.set_xlabel("element size h (m)")
    left.set_ylabel("m")
    left.invert_xaxis()
    left.legend(fontsize=8)
    left.grid(alpha=0.3)
    coarse = rows[1:]  # all but the finest (the reference)
    for key, label, marker in (("runout_difference_to_finest_m", "runout", "o"),
                               ("slip_radius_difference_to_finest_m", "slip circle radius", "s")):
        pts = [(r["mesh_size_m"], r[key]) for r in coarse if r[key] > 0 and math.isfinite(r[key])]
        if pts:
            right.loglog([p[0] for p in pts], [p[1] for p in pts], marker + "-", label=label)
    right.set_xlabel("element size h (m)")
    right.set_ylabel("|q_h - q_finest| (m)")
    right.legend(fontsize=8)
    right.grid(True, which="both", alpha=0.3)
    fig.suptitle(f"Slope: convergence with element size (finest h = {rows[0]['mesh_size_m']:g} m)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_energy(rows, path):
    fig, ax = plt.subplots(figsize=(7.5, 4))
    t = [r["time_s"] for r in rows]
    ax.plot(t, [r["drift_particle"] * 100 for r in rows], lw=0.8, label="with the particle kinetic energy")
    ax.plot(t, [r["drift_grid"] * 100 for r in rows], lw=0.8, ls="--", label="with the grid kinetic energy")
    ax.legend(fontsize=8)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("(E(t) - E(0)) / max strain energy (%)")
    ax.set_title("Spring and mass, 1e5 steps: drift of kinetic + potential + strain energy", fontsize=10)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_column(rows, path):
    """Runout (L_inf - L0) / L0 against the aspect ratio a, log axes, with Lube et al. (2005)."""
    fig, ax = plt.subplots(figsize=(6, 4.5))
    low = [a / 10 for a in range(3, 19)]
    high = [2.8 + a / 10 for a in range(0, 53)]
    ax.plot(low, [1.2 * a for a in low], "k-", lw=1.2, label="Lube et al. 2005: 1.2 a (a < 1.8)")
    ax.plot(high, [1.9 * a ** (2 / 3) for a in high], "k--", lw=1.2, label="1.9 a^(2/3) (a > 2.8)")
    for k, name in enumerate(sorted({r["transfer"] for r in rows})):
        colour = "C%d" % k
        mine = [r for r in rows if r["transfer"] == name and r["runout_ratio"] != ""]
        if mine:
            ax.plot([r["aspect_ratio"] for r in mine], [r["runout_ratio"] for r in mine], "o-", ms=5, lw=0.8,
                    color=colour, label=name + " (deposit tip)")
        post = [r for r in rows if r["transfer"] == name and r["post_runout_ratio"] != ""]
        if post:
            ax.plot([r["aspect_ratio"] for r in post], [r["post_runout_ratio"] for r in post], "s--", ms=5, lw=0.8,
                    color=colour, markerfacecolor="none", label=name + " (talus post)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("aspect ratio a = H0 / L0")
    ax.set_ylabel("(L_inf - L0) / L0")
    ax.set_title("Column collapse: runout against aspect ratio", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_rods(rows, path):
    """The aluminium rods: runout and final height against a, with Nguyen et al. (2015)'s laws."""
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4.2))
    low = [0.65 + k * 0.85 / 20 for k in range(21)]
    high = [1.5 + k * 4.5 / 40 for k in range(41)]
    left.plot(low, [3.25 * a ** 0.96 for a in low], "k-", lw=1.2, label="3.25 a^0.96 (0.65 < a < 1.5)")
    left.plot(high, [3.80 * a ** 0.73 for a in high], "k--", lw=1.2, label="3.80 a^0.73 (a > 1.5)")
    band = low + high
    right.plot(band, [1.42 * a ** (2 / 3) for a in band], "k-", lw=1.2, label="1.42 a^(2/3)")
    for k, name in enumerate(sorted({r["transfer"] for r in rows})):
        colour = "C%d" % k
        mine = [r for r in rows if r["transfer"] == name and r["runout_ratio"] != ""]
        post = [r for r in rows if r["transfer"] == name and r["post_runout_ratio"] != ""]
        if mine:
            left.plot([r["aspect_ratio"] for r in mine], [r["runout_ratio"] for r in mine], "o-", ms=5, lw=0.8,
                      color=colour, label=name + " (deposit tip)")
        if post:
            left.plot([r["aspect_ratio"] for r in post], [r["post_runout_ratio"] for r in post], "s--", ms=5,
                      lw=0.8, color=colour, markerfacecolor="none", label=name + " (talus post)")
        height = [r for r in rows if r["transfer"] == name and r["height_ratio"] != ""]
        if height:
            right.plot([r["aspect_ratio"] for r in height], [r["height_ratio"] for r in height], "o-", ms=5,
                       lw=0.8, color=colour, label=name)
    for ax, label in ((left, "(d - d0) / d0"), (right, "h0 / h")):
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("aspect ratio a = h0 / d0")
        ax.set_ylabel(label)
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    left.set_title("Aluminium rods: runout (Nguyen et al. 2015)", fontsize=10)
    right.set_title("Aluminium rods: final height", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    if len(sys.argv) != 3 or sys.argv[1] not in ("accuracy", "stability", "runout"):
        print(__doc__, file=sys.stderr)
        return 1
    what, out = sys.argv[1], sys.argv[2]
    written = []
    if what == "accuracy":
        for scene in ("spring_mass", "box_incline"):
            source = os.path.join(out, f"accuracy_{scene}.csv")
            if os.path.exists(source):
                rows = read_csv(source)
                if rows:
                    written.append(os.path.join(out, f"bench_accuracy_{scene}.png"))
                    plot_error_against_time(rows, scene, written[-1])
        source = os.path.join(out, "accuracy_slope.csv")
        if os.path.exists(source) and len(read_csv(source)) >= 2:
            written.append(os.path.join(out, "bench_accuracy_slope.png"))
            plot_slope(read_csv(source), written[-1])
    elif what == "runout":
        source = os.path.join(out, "runout_column.csv")
        if os.path.exists(source) and read_column_csv(source):
            written.append(os.path.join(out, "bench_runout_column.png"))
            plot_column(read_column_csv(source), written[-1])
        source = os.path.join(out, "runout_rods.csv")
        if os.path.exists(source) and read_column_csv(source):
            written.append(os.path.join(out, "bench_runout_rods.png"))
            plot_rods(read_column_csv(source), written[-1])
    else:
        source = os.path.join(out, "stability_energy.csv")
        if os.path.exists(source):
            written.append(os.path.join(out, "bench_stability_energy.png"))
            plot_energy(read_csv(source), written[-1])
    for path in written:
        print(f"wrote {path}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
