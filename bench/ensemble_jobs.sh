#!/usr/bin/env bash
# `talus ensemble`'s throughput on --jobs 1 and --jobs 2 (docs/benchmarks.md, "Ensemble"):
# ROUNDS alternating rounds of the same ensemble on each, every run in a fresh folder, then the
# median wall time of the realisations, the realisations per hour and the overhead's share of
# the solves (ensemble.json's timing), and the ratio of the medians.
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

for round in $(seq "$rounds"); do
  for jobs in 1 2; do
    out="$work/r${round}_j${jobs}"
    "$talus" ensemble "$scene" --realisations "$count" --jobs "$jobs" --out "$out" -q "$@" >/dev/null
    echo "$jobs $(timing "$out")" | tee -a "$work/runs"
  done
done
/usr/bin/python3 - "$work/runs" <<'EOF'
import statistics, sys
runs = [line.split() for line in open(sys.argv[1])]
median = {}
for jobs in ("1", "2"):
    rows = [r for r in runs if r[0] == jobs]
    wall = statistics.median(float(r[1]) for r in rows)
    per_hour = statistics.median(float(r[2]) for r in rows)
    overhead = statistics.median(float(r[3]) for r in rows)
    median[jobs] = wall
    print(f"--jobs {jobs}: median wall {wall:.2f} s, {per_hour:.0f} realisations per hour, overhead {100 * overhead:.2f} % of the solves")
print(f"--jobs 2 against --jobs 1: {median['1'] / median['2']:.2f} x the throughput")
EOF
