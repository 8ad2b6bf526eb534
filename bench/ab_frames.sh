#!/usr/bin/env bash
# Do two builds give the same frames? Every shipped scene (and the transfers, softening and
# mixed integration on small variants) is meshed and solved by each build, on 1 and 2 threads
# and, where both builds have MPI, on 2 ranks; the frames of results.h5 are compared bit for bit
# (bench/compare_frames.py). A refactor must print "identical" on every row.
#
#   bench/ab_frames.sh OLD_BUILD_DIR NEW_BUILD_DIR [CASE_FILTER]
#
# Each build meshes its own model.h5 (the two may write different model formats); the cases are
# short (a coarse mesh, a few hundred steps), about 3 minutes in all on two cores.
set -uo pipefail
old="$1"; new="$2"; filter="${3:-}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="${AB_FRAMES_WORK:-$(mktemp -d)}"; mkdir -p "$work"
[ -n "${AB_FRAMES_WORK:-}" ] || trap 'rm -rf "$work"' EXIT
python=/usr/bin/python3
g="$root/geometries"

# name | scene | overrides (space-separated --set values)
cases=(
  "slope|$g/slope.toml|mesh.size=0.5 run.end_time=1.0 run.output_interval=0.25"
  "slope_delaunay_evs|$g/slope.toml|mesh.size=0.5 mesh.pattern=delaunay run.evs=true run.end_time=0.6 run.output_interval=0.2"
  "slope_bspline|$g/slope.toml|mesh.size=0.5 mesh.pattern=grid run.shape_functions=bspline run.end_time=0.6 run.output_interval=0.2"
  "slope_bspline_apic|$g/slope.toml|mesh.size=0.5 mesh.pattern=grid run.shape_functions=bspline run.transfer=apic run.end_time=0.6 run.output_interval=0.2"
  "slope_xpic|$g/slope.toml|mesh.size=0.5 run.transfer=xpic run.xpic_order=3 run.end_time=0.6 run.output_interval=0.2"
  "slope_pic|$g/slope.toml|mesh.size=0.5 run.transfer=pic_blend run.pic_fraction=0.05 run.end_time=0.6 run.output_interval=0.2"
  "slope_softening|$g/slope.toml|mesh.size=0.5 materials.sand.softening_end=0.5 materials.sand.residual_friction_angle=20 run.end_time=0.6 run.output_interval=0.2"
  "spring_mass|$g/spring_mass.toml|run.end_time=0.03 run.output_interval=0.01"
  "box_incline|$g/box_incline.toml|run.end_time=0.2 run.output_interval=0.05"
  "column|$g/column_collapse.toml|mesh.size=0.01 run.end_time=0.2 run.output_interval=0.05"
  "griffiths_lane|$g/griffiths_lane.toml|mesh.size=1.0 run.end_time=0.5 run.output_interval=0.25"
  "two_layer_clay|$g/two_layer_clay.toml|mesh.size=1.0 run.end_time=0.5 run.output_interval=0.25"
  "layered_slope|$g/layered_slope.toml|mesh.size=0.5 run.end_time=0.5 run.output_interval=0.25"
  "fredlund_krahn|$g/fredlund_krahn.toml|mesh.size=1.0 run.end_time=0.5 run.output_interval=0.25"
  "rising_water|$g/rising_water.toml|mesh.size=0.5 run.end_time=0.5 run.output_interval=0.25"
)

has_mpi() { "$1/bin/talus" --help 2>&1 | grep -q -- "--ranks"; }
runs=("t1|--threads 1" "t2|--threads 2")
if has_mpi "$old" && has_mpi "$new" && command -v mpirun >/dev/null; then runs+=("r2|--ranks 2 --threads 1"); fi

status=0
for entry in "${cases[@]}"; do
  IFS='|' read -r name scene overrides <<< "$entry"
  [ -n "$filter" ] && [[ "$name" != *$filter* ]] && continue
  sets=()
  for o in $overrides; do sets+=(--set "$o"); done
  for build in old new; do
    dir="$old"; [ "$build" = new ] && dir="$new"
    if ! "$dir/bin/talus" mesh "$scene" "${sets[@]}" --out "$work/$name/$build" --quiet 2> "$work/$name.$build.mesh.log"; then
      echo "| $name | mesh failed ($build): $(tail -1 "$work/$name.$build.mesh.log") |"; status=1; continue 2
    fi
  done
  for run in "${runs[@]}"; do
    IFS='|' read -r label flags <<< "$run"
    for build in old new; do
      dir="$old"; [ "$build" = new ] && dir="$new"
      # shellcheck disable=SC2086
      "$dir/bin/talus" solve "$work/$name/$build/model.h5" --out "$work/$name/$build.$label" $flags --quiet \
        > "$work/$name.$build.$label.log" 2>&1
      echo "$?" > "$work/$name.$build.$label.rc"
    done
    old_rc=$(cat "$work/$name.old.$label.rc"); new_rc=$(cat "$work/$name.new.$label.rc")
    if [ ! -f "$work/$name/old.$label/results.h5" ] && [ ! -f "$work/$name/new.$label/results.h5" ] &&
       [ "$old_rc" = "$new_rc" ] && [ "$old_rc" != 0 ]; then
      # Both builds refuse the case alike (XPIC(m > 1) or mixed integration on several ranks).
      verdict="identical refusal (exit $old_rc): $(tail -1 "$work/$name.new.$label.log")"
    else
      verdict=$("$python" "$root/bench/compare_frames.py" "$work/$name/old.$label/results.h5" \
        "$work/$name/new.$label/results.h5" 2>&1)
      [ "$old_rc" = "$new_rc" ] || verdict="exit $old_rc against $new_rc; $verdict"
    fi
    case "$verdict" in identical*) ;; *) status=1 ;; esac
    echo "| $name | $label | $verdict |"
  done
done
exit "$status"
