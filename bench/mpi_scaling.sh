#!/usr/bin/env bash
# Strong scaling of the distributed solve on this machine (docs/scaling.md): the default slope
# meshed finely enough for about 2M particles, solved for a fixed number of steps on 1 rank and
# on 2 ranks (one OpenMP thread per rank), several rounds in alternation; prints each run's
# time loop, the medians, the parallel efficiency T1 / (2 T2) and the bytes the ranks exchange
# per step. Run it on a quiet machine.
#
#   bench/mpi_scaling.sh [SIZE] [STEPS] [ROUNDS]     defaults: 0.014 m (2.0M particles), 150, 3
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
size="${1:-0.014}"
steps="${2:-150}"
rounds="${3:-3}"
work="${TALUS_SCALING_DIR:-/tmp/talus-mpi-scaling}"
talus="$root/talus"
export OMP_WAIT_POLICY=PASSIVE
mkdir -p "$work"
model="$work/h$size-s$steps/model.h5"
if [ ! -f "$model" ]; then
  echo "meshing the slope at mesh.size=$size (once)" >&2
  "$talus" mesh "$root/geometries/slope.toml" --set "mesh.size=$size" --set "run.max_steps=$steps" \
    --set run.output_interval=100 --out "$(dirname "$model")" --quiet
fi
loop_seconds() { sed -n 's/.*time loop \([0-9.]*\) s.*/\1/p' "$1"; }
median() { sort -g | awk '{a[NR]=$1} END {print (NR % 2 ? a[(NR+1)/2] : (a[NR/2] + a[NR/2+1]) / 2)}'; }
one=() two=()
for round in $(seq 1 "$rounds"); do
  for ranks in 1 2; do
    log="$work/run-$ranks-$round.log"
    "$talus" solve "$model" --threads 1 --ranks "$ranks" --out "$work/out-$ranks" >"$log" 2>&1
    t="$(loop_seconds "$log")"
    echo "round $round, $ranks rank(s): time loop $t s" >&2
    if [ "$ranks" = 1 ]; then one+=("$t"); else two+=("$t"); fi
  done
done
t1="$(printf '%s\n' "${one[@]}" | median)"
t2="$(printf '%s\n' "${two[@]}" | median)"
particles="$(sed -n 's/.* steps, \([0-9]*\) particles.*/\1/p' "$work/run-1-1.log")"
bytes="$(sed -n 's/.*MPI ranks: \([0-9]*\) bytes.*/\1/p' "$work/run-2-1.log")"
echo "particles $particles, steps $steps"
echo "1 rank:  median time loop $t1 s"
echo "2 ranks: median time loop $t2 s"
awk -v a="$t1" -v b="$t2" 'BEGIN {printf "speed-up %.3f, parallel efficiency %.1f %%\n", a / b, 100 * a / (2 * b)}'
echo "bytes exchanged at shared nodes per step, both ranks: $bytes"
grep -h "MPI ranks" "$work/run-2-1.log" || true
