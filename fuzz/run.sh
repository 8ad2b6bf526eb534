#!/usr/bin/env bash
# The fuzz test of the suite: builds the fuzzers (build.sh) and runs each for SECONDS over the
# committed corpus fuzz/corpus/NAME (read only; new inputs go to OUT/corpus/NAME). Fails on any
# crash, sanitizer report, leak or uncaught exception (libFuzzer exits non-zero, leaving
# OUT/crash-* or leak-* with the input).
#   fuzz/run.sh OUT SECONDS "HDF5_INCLUDE_DIRS" "HDF5_LIBRARIES" [NAMES, default "scene model_structure"]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$1"; seconds="${2:-30}"
"$root/fuzz/build.sh" "$out" "${3:-}" "${4:-}"
export LSAN_OPTIONS="suppressions=$root/fuzz/lsan.supp:print_suppressions=0"
# As in the real program, a malloc too large returns NULL (HDF5 then reports an error) instead
# of ending the run: HDF5 1.10.8 asks for sizes read from a damaged file before checking them.
# Slow unwinding: libhdf5 has no frame pointers, and the suppression needs its frames. It is
# only needed for the damaged files of model_fuzzer, and makes the others ~3x slower.
status=0
for name in ${5:-scene model_structure}; do
  unwind=1
  if [ "$name" = model ]; then unwind=0; fi
  export ASAN_OPTIONS="allocator_may_return_null=1:fast_unwind_on_malloc=$unwind"
  mkdir -p "$out/corpus/$name"
  echo "fuzz: ${name}_fuzzer for $seconds s"
  # A hang inside the HDF5 library on a damaged file (HDF5 1.10.8's global heap, see
  # docs/robustness.md) cannot be fixed here: a timeout is reported, with its input, but does
  # not fail the test; crashes, leaks and uncaught exceptions do.
  if ! "$out/${name}_fuzzer" -max_total_time="$seconds" -timeout=10 -timeout_exitcode=0 -rss_limit_mb=2048 \
       -print_final_stats=1 \
       -artifact_prefix="$out/" "$out/corpus/$name" "$root/fuzz/corpus/$name" 2>"$out/$name.log"; then
    status=1
  fi
  grep -E "^(stat::number_of_executed_units|stat::new_units_added|#[0-9]+ +DONE)|ERROR|SUMMARY" "$out/$name.log" || true
  if grep -q "libFuzzer: timeout" "$out/$name.log"; then echo "fuzz: warning: ${name}_fuzzer timed out (see $out/timeout-*)"; fi
done
exit $status
