#!/usr/bin/python3
"""Two builds' step phases on one model, alternately, the order swapped every round.

    bench/ab_phases.py OLD_BUILD_DIR NEW_BUILD_DIR MODEL.h5 THREADS [ROUNDS]   (default 6 rounds)

Runs BUILD/bin/talus_bench_throughput --model MODEL.h5 THREADS from each build in turn and prints
the median (and range) of the time loop, the particle-update rate and each phase's ns per
particle-update. On a 2-core machine the second run of a pair is often the slower one
(docs/benchmarks.md), hence the swapped order. Make MODEL.h5 with `talus mesh SCENE --out DIR`.
"""
import collections
import re
import statistics
import subprocess
import sys


def main():
    if len(sys.argv) not in (5, 6):
        sys.exit(__doc__)
    old, new, model, threads = sys.argv[1:5]
    rounds = int(sys.argv[5]) if len(sys.argv) == 6 else 6
    builds = {"old": old, "new": new}
    found = {name: collections.defaultdict(list) for name in builds}
    for r in range(rounds):
        for name in (("old", "new") if r % 2 == 0 else ("new", "old")):
            run = subprocess.run([f"{builds[name]}/bin/talus_bench_throughput", "--model", model, threads],
                                 capture_output=True, text=True)
            if run.returncode != 0:
                sys.exit(f"{builds[name]}: talus_bench_throughput failed:\n{run.stderr}")
            for line in run.stdout.splitlines():
                loop = re.search(r"time loop ([0-9.]+) s, ([0-9.e+]+) particle-updates/s", line)
                if loop:
                    found[name]["time loop (s)"].append(float(loop.group(1)))
                    found[name]["particle-updates/s"].append(float(loop.group(2)))
                phase = re.match(r"\s+(\S.*?)\s+([0-9.]+) ns", line)
                if phase:
                    found[name][phase.group(1) + " (ns)"].append(float(phase.group(2)))
    print(f"| {threads} threads, {rounds} rounds | old (median) | new (median) | old range | new range |")
    print("|---|---:|---:|---|---|")
    for key, before in found["old"].items():
        after = found["new"][key]
        if max(before + after) == 0:
            continue
        print(f"| {key} | {statistics.median(before):.4g} | {statistics.median(after):.4g} "
              f"| {min(before):.4g}-{max(before):.4g} | {min(after):.4g}-{max(after):.4g} |")


if __name__ == "__main__":
    main()
