#!/usr/bin/python3
"""The settlement of a strip footing against its pressure (bench/footing/footing.toml, docs/slope.md).

    /usr/bin/python3 bench/footing/settlement.py RESULTS.h5 [RESULTS.h5 ...] --pressure P --ramp T --cohesion C

For each results.h5: the footing's settlement, the mean vertical displacement of the particles
that start under the footing (x < --half-width) within 0.2 m of the clay's top, at every frame,
against the pressure of the load's ramp at that time, p(t) = P (1 - cos(pi t / T)) / 2 (P after
T); printed as the pressure over c at which the settlement first reaches 0.02, 0.05, 0.1 and
0.2 footing widths ("-" if it does not).
"""
import argparse

import h5py
import numpy as np

LEVELS = (0.02, 0.05, 0.1, 0.2)


def pressure_at_levels(path, pressure, ramp, cohesion, half_width):
    with h5py.File(path, "r") as f:
        x0 = f["particles/initial_position"][:]
        under = (x0[:, 0] < half_width) & (x0[:, 1] > x0[:, 1].max() - 0.2)
        t = f["frames/time"][:]
        settlement = -f["frames/displacement"][:, under, 1].mean(axis=1)
    q = pressure * (1 - np.cos(np.pi * np.minimum(t, ramp) / ramp)) / 2 / cohesion
    width = 2 * half_width
    found = []
    for level in LEVELS:
        reached = np.nonzero(settlement >= level * width)[0]
        found.append(q[reached[0]] if reached.size else None)
    return len(x0), found, settlement[-1]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("results", nargs="+")
    parser.add_argument("--pressure", type=float, required=True, help="the load's pressure, Pa")
    parser.add_argument("--ramp", type=float, required=True, help="the load's ramp, s")
    parser.add_argument("--cohesion", type=float, required=True, help="c, Pa")
    parser.add_argument("--half-width", type=float, default=0.5, help="the footing's half-width b, m (0.5)")
    args = parser.parse_args()
    print("| results | particles | " + " | ".join("p / c at %g B" % level for level in LEVELS) + " | last settlement (m) |")
    print("|---|---:|" + "---:|" * len(LEVELS) + "---:|")
    for path in args.results:
        particles, found, last = pressure_at_levels(path, args.pressure, args.ramp, args.cohesion, args.half_width)
        cells = " | ".join("-" if q is None else "%.2f" % q for q in found)
        print("| %s | %d | %s | %.3f |" % (path, particles, cells, last))


if __name__ == "__main__":
    main()
