#!/usr/bin/env bash
# `talus ensemble`'s throughput on --jobs 1, --jobs 2 and, when talus has MPI, --ranks 2 --jobs 1
# (docs/benchmarks.md, "Ensemble"): ROUNDS alternating rounds of the same ensemble on each, every
# run in a fresh folder, then the median wall time of the realisations, the realisations per hour
# and the overhead's share of the solves (ensemble.json's timing: with --ranks, rank 0's time from
# the first realisation to the last, without mpirun's start), and the ratios of the medians.
#
#   bench/ensemble_jobs.sh [ROUNDS] [N] [--set KEY=VALUE]...
#   bench/ensemble_jobs.sh 3 8 --set run.end_time=2
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
talus="${TALUS_BINARY:-$root/build/bin/talus}"
rounds="${1:-3}"
count="${2:-8}"
shift $(( $# > 2 ? 2 : $# ))
scene="$root/geometries/slope_random.toml"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

timing() {  # wall_s, realisations_per_hour and overhead_of_solve of one run's ensemble.json
  /usr/bin/python3 -c 'import json, sys; t = json.load(open(sys.argv[1]))["timing"]
print(t["wall_s"], t["realisations_per_hour"], t["overhead_of_solve"])' "$1/ensemble.json"
}

configurations=("j1" "j2")
if "$talus" --version | grep -q "(with MPI"; then configurations+=("r2"); fi
options() {  # the options of a configuration
  case "$1" in j1) echo "--jobs 1" ;; j2) echo "--jobs 2" ;; r2) echo "--ranks 2 --jobs 1" ;; esac
}
for round in $(seq "$rounds"); do
  for configuration in "${configurations[@]}"; do
    out="$work/r${round}_${configuration}"
    # shellcheck disable=SC2046  # the options are words
    "$talus" ensemble "$scene" --realisations "$count" $(options "$configuration") --out "$out" -q "$@" >/dev/null
    echo "$configuration $(timing "$out")" | tee -a "$work/runs"
  done
done
/usr/bin/python3 - "$work/runs" <<'EOF'
import statistics, sys
runs = [line.split() for line in open(sys.argv[1])]
names = {"j1": "--jobs 1", "j2": "--jobs 2", "r2": "--ranks 2 --jobs 1"}
median = {}
for configuration in names:
    rows = [r for r in runs if r[0] == configuration]
    if not rows:
        continue
    wall = statistics.median(float(r[1]) for r in rows)
    per_hour = statistics.median(float(r[2]) for r in rows)
    overhead = statistics.median(float(r[3]) for r in rows)
    median[configuration] = wall
    print(f"{names[configuration]}: median wall {wall:.2f} s, {per_hour:.0f} realisations per hour, overhead {100 * overhead:.2f} % of the solves")
for configuration in ("j2", "r2"):
    if configuration in median:
        print(f"{names[configuration]} against --jobs 1: {median['j1'] / median[configuration]:.2f} x the throughput")
EOF
