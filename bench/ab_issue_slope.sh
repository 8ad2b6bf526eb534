#!/usr/bin/env bash
# Item 4 of issue 15: the Mohr-Coulomb + EVS slope at 48,812 particles on 2 threads, two builds
# each solving the slope its own `talus mesh` makes, the order alternated every round. Run it on
# a quiet machine:
#
#   bench/ab_issue_slope.sh OLD_BUILD_DIR NEW_BUILD_DIR [ROUNDS]     (default 8 rounds)
#
# The slope is Delaunay triangles with EVS, as issue 15 measured it (63be605's defaults; a build
# that knows mesh.pattern and run.evs is given them). Prints each build's time loop (median and
# range), the ratio of the medians and the median of the rounds' own ratios old / new.
set -euo pipefail
old="$1"; new="$2"; rounds="${3:-8}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# A build older than mesh.pattern rejects the scene's `pattern` key: it gets the scene as it was
# (no pattern, EVS on), beside slope.geo so that the geometry's relative path holds.
old_scene="$root/geometries/.slope-before-pattern-$$.toml"
work="$(mktemp -d)"; trap 'rm -rf "$work" "$old_scene"' EXIT
sed -e '/^pattern *=/d' -e 's/^evs *= *false/evs = true/' "$root/geometries/slope.toml" > "$old_scene"
for b in old new; do
  dir="$old"; [ "$b" = new ] && dir="$new"
  steps=(--set mesh.size=0.0884 --set run.max_steps=1500)
  "$dir/bin/talus" mesh "$root/geometries/slope.toml" "${steps[@]}" --set mesh.pattern=delaunay --set run.evs=true \
    --out "$work/$b" --quiet >/dev/null 2>&1 || "$dir/bin/talus" mesh "$old_scene" "${steps[@]}" --out "$work/$b" --quiet
done
for r in $(seq "$rounds"); do
  order="old new"; [ $((r % 2)) = 0 ] && order="new old"
  for b in $order; do
    dir="$old"; [ "$b" = new ] && dir="$new"
    "$dir/bin/talus" solve "$work/$b/model.h5" --threads 2 --out "$work/out_$b" |
      grep -o "[0-9]* particles, .* time loop [0-9.]* s" |
      awk -v b="$b" -v r="$r" '{print r, b, $(NF - 1), $1}' >> "$work/times"
  done
done
/usr/bin/python3 - "$work/times" <<'EOF'
import statistics, sys
rows = [line.split() for line in open(sys.argv[1])]
t = {b: {r: float(s) for r, bb, s, _ in rows if bb == b} for b in ("old", "new")}
for b in ("old", "new"):
    print(f"{b}: particles {sorted({int(n) for _, bb, _, n in rows if bb == b})}")
old, new = list(t["old"].values()), list(t["new"].values())
ratios = [t["old"][r] / t["new"][r] for r in t["old"]]
for name, v in (("old", old), ("new", new)):
    print(f"{name}: time loop median {statistics.median(v):.2f} s ({min(v):.2f}-{max(v):.2f} s)")
print(f"ratio of the medians {statistics.median(old) / statistics.median(new):.3f}, "
      f"median of the {len(ratios)} rounds' ratios {statistics.median(ratios):.3f} "
      f"({min(ratios):.2f}-{max(ratios):.2f})")
EOF
