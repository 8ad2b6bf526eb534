#!/usr/bin/env bash
# Builds the libFuzzer targets with clang++ (-fsanitize=fuzzer,address), apart from the main
# g++ build: every source of common/ (and its folders) plus each fuzz/*_fuzzer.cpp, objects in OUT/obj, rebuilt when their
# source or a header of common/ is newer. toml++ is compiled header-only here, so that the
# TOML parser is instrumented too. -DNDEBUG as in the Release build: the findings are those
# of the program users run (toml++ 3.3 has internal assertions that fuzzing trips, see
# docs/robustness.md).
#   fuzz/build.sh OUT "HDF5_INCLUDE_DIRS" "HDF5_LIBRARIES"
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$1"; hdf5_includes="${2:-/usr/include/hdf5/serial}"; hdf5_libraries="${3:-}"
mkdir -p "$out/obj"
flags=(-std=c++20 -O1 -g -fno-omit-frame-pointer -fsanitize=fuzzer-no-link,address
       -DNDEBUG -DTALUS_VERSION=\"0.1.0\" -DTOML_HEADER_ONLY=1 -I"$root" -I/usr/include/eigen3)
for dir in $hdf5_includes; do flags+=(-I"$dir"); done
libraries=()
if [ -n "$hdf5_libraries" ]; then
  for library in $hdf5_libraries; do libraries+=("$library"); done
else
  libraries=(-lhdf5_serial)
fi
# Objects built with other flags are stale too.
if [ "$(cat "$out/obj/flags" 2>/dev/null)" != "${flags[*]}" ]; then rm -f "$out"/obj/*.o; fi
echo "${flags[*]}" > "$out/obj/flags"
newest_header="$(find "$root/common" -name '*.hpp' -printf '%T@ %p\n' | sort -n | tail -1 | cut -d' ' -f2)"
objects=()
compile() {  # source object
  if [ ! -f "$2" ] || [ "$1" -nt "$2" ] || [ "$newest_header" -nt "$2" ]; then
    clang++ "${flags[@]}" -c "$1" -o "$2"
  fi
}
while IFS= read -r source; do
  relative="${source#"$root"/common/}"
  object="$out/obj/${relative//\//_}"; object="${object%.cpp}.o"
  compile "$source" "$object" &
  objects+=("$object")
done < <(find "$root/common" -name '*.cpp' | sort)
wait
for fuzzer in scene_fuzzer model_fuzzer model_structure_fuzzer; do
  compile "$root/fuzz/$fuzzer.cpp" "$out/obj/$fuzzer.o"
  clang++ -fsanitize=fuzzer,address "$out/obj/$fuzzer.o" "${objects[@]}" "${libraries[@]}" -o "$out/$fuzzer"
done
