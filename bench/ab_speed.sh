#!/usr/bin/env bash
# The speed table of docs/benchmarks.md ("Before and after"), two builds alternately, run by
# run, so that a change in the machine's load hits both alike. Run it on a quiet machine:
#
#   bench/ab_speed.sh OLD_BUILD_DIR NEW_BUILD_DIR [REPEATS]      (default 5 repeats)
#
# Rows: the 50k elastic block on 1 and 2 threads, the 10M block on 2 threads (rate and bytes
# per particle), the Mohr-Coulomb + EVS slope at 48.8k particles (default threads: the new
# build chooses, the old one uses all cores), the 4k block (default threads) and the slope
# under one busy program per core (talus_bench_load). Medians of REPEATS runs.
set -euo pipefail
old="$1"; new="$2"; repeats="${3:-5}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="$(mktemp -d)"; trap 'rm -rf "$work"' EXIT
median() { sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }

block() {  # block PARTICLES THREADS: "rate bytes" medians for old and new
  local n="$1" t="$2"
  for r in $(seq "$repeats"); do
    for b in old new; do
      dir="$old"; [ "$b" = new ] && dir="$new"
      "$dir/bin/talus_bench_throughput" --case "$n" "$t" | awk -v b="$b" '{print b, $4, $5}' >> "$work/block_${n}_$t"
    done
  done
  for b in old new; do
    rate=$(grep "^$b " "$work/block_${n}_$t" | cut -d' ' -f2 | median)
    bytes=$(grep "^$b " "$work/block_${n}_$t" | cut -d' ' -f3 | median)
    echo "| elastic block $n, $t threads | $b | $rate particle-updates/s | $bytes bytes/particle |"
  done
}

slope() {  # slope MESH_SIZE LABEL: time loop medians, default threads
  local size="$1" label="$2"
  # The slope as issue 15 measured it: Delaunay triangles with EVS (the scene's default is now
  # crossed triangles without EVS, docs/slope.md).
  "$new/bin/talus" mesh "$root/geometries/slope.toml" --set mesh.size="$size" --set run.max_steps=1500 \
    --set mesh.pattern=delaunay --set run.evs=true --out "$work/slope_$label" --quiet
  for r in $(seq "$repeats"); do
    for b in old new; do
      dir="$old"; [ "$b" = new ] && dir="$new"
      "$dir/bin/talus" solve "$work/slope_$label/model.h5" | grep -o "time loop [0-9.]* s on [^,(]*\(([^)]*)\)\?" |
        sed "s/^/$b /" >> "$work/slope_$label.txt"
    done
  done
  for b in old new; do
    t=$(grep "^$b " "$work/slope_$label.txt" | awk '{print $4}' | median)
    how=$(grep "^$b " "$work/slope_$label.txt" | head -1 | sed 's/.* s on //')
    echo "| slope $label (1500 steps), default threads | $b | time loop $t s | $how |"
  done
}

echo "| case | build | median of $repeats | |"
echo "|---|---|---|---|"
block 50000 1
block 50000 2
block 4000 1
block 4000 2
slope 0.0884 "48.8k"
slope 0.25 "6.2k"
block 10000000 2
"$new/bin/talus_bench_load" --talus "$old/bin/talus" --talus "$new/bin/talus" --repeats "$repeats"
