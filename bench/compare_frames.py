"""Compares the frames of two results.h5 files bit for bit (bench/ab_frames.sh).

    /usr/bin/python3 bench/compare_frames.py A/results.h5 B/results.h5

Prints "identical (F frames, P particles)" when every dataset under /frames and /history that
both files hold has the same shape and the same bits, else the first dataset that differs and
by how much. Datasets that only one file holds are named (a new field is not a difference in
the frames both hold).
"""
import sys

import h5py
import numpy as np


def main(a_path, b_path):
    try:
        a, b = h5py.File(a_path, "r"), h5py.File(b_path, "r")
    except OSError as error:
        print(f"cannot open: {error}")
        return 1
    differences, only = [], []
    for group in ("frames", "history"):
        if group not in a or group not in b:
            only.append(group)
            continue
        for name in sorted(set(a[group]) | set(b[group])):
            if name not in a[group] or name not in b[group]:
                only.append(f"{group}/{name}")
                continue
            x, y = a[group][name][()], b[group][name][()]
            if x.shape != y.shape:
                differences.append(f"{group}/{name}: shape {x.shape} against {y.shape}")
                continue
            same = np.array_equal(x.view(np.uint8), y.view(np.uint8)) if x.dtype == y.dtype else False
            if not same:
                with np.errstate(invalid="ignore"):
                    gap = np.nanmax(np.abs(x.astype(float) - y.astype(float))) if x.size else 0.0
                differences.append(f"{group}/{name}: max difference {gap:.3g}")
    frames = a["frames/time"].shape[0] if "frames/time" in a else 0
    particles = int(a.attrs.get("particles", 0))
    extra = f"; only in one file: {', '.join(only)}" if only else ""
    if differences:
        print(f"DIFFERENT: {'; '.join(differences[:3])}{extra}")
        return 1
    print(f"identical ({frames} frames, {particles} particles){extra}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
