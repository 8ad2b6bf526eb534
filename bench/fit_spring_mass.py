"""Fits the spring and mass's settlement y(t) = A (1 - cos(omega t)) to a run's spring_mass.csv
(written by talus post, docs/postproc.md) by least squares, to tell a wrong stiffness (omega off)
from a wrong static settlement (A off) (docs/shape-functions.md, "Spring and mass").

    /usr/bin/python3 bench/fit_spring_mass.py OUT/spring_mass.csv [OMEGA]

OMEGA (rad/s, default 100, the scene's): the search runs over 0.8 to 1.2 times it. For each
omega the best A is linear, sum(y f) / sum(f^2) with f = 1 - cos(omega t); omega is the one of
least squared residual, from a scan refined by golden-section search. Prints A (mm), omega
(rad/s) and the largest residual over A.
"""
import math
import sys

import numpy as np


def fit(t, y, omega0):
    def residual(omega):
        f = 1 - np.cos(omega * t)
        amplitude = float(np.dot(y, f) / np.dot(f, f))
        return float(np.sum((y - amplitude * f) ** 2)), amplitude

    grid = np.linspace(0.8 * omega0, 1.2 * omega0, 401)
    best = min(grid, key=lambda w: residual(w)[0])
    step = grid[1] - grid[0]
    lo, hi = best - step, best + step
    ratio = (math.sqrt(5) - 1) / 2
    while hi - lo > 1e-9 * omega0:
        a, b = hi - ratio * (hi - lo), lo + ratio * (hi - lo)
        if residual(a)[0] < residual(b)[0]:
            hi = b
        else:
            lo = a
    omega = 0.5 * (lo + hi)
    amplitude = residual(omega)[1]
    worst = float(np.max(np.abs(y - amplitude * (1 - np.cos(omega * t)))))
    return amplitude, omega, worst


def main(path, omega0=100.0):
    data = np.genfromtxt(path, delimiter=",", names=True)
    amplitude, omega, worst = fit(data["time_s"], data["mpm_m"], omega0)
    print(f"A = {amplitude * 1e3:.4f} mm  omega = {omega:.2f} rad/s  largest residual / A = {worst / amplitude:.4f}")


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    main(sys.argv[1], float(sys.argv[2]) if len(sys.argv) == 3 else 100.0)
