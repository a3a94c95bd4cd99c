#!/usr/bin/env bash
# Runs each libFuzzer target of a fuzzing build for a bounded time (make fuzz).
#
#   tests/fuzz/run.sh BUILD SECONDS TARGET...
#
# The corpus of each target lives in BUILD/corpus/TARGET (kept between runs), seeded from
# tests/fuzz/seeds/TARGET and tests/fuzz/regressions/TARGET. A crash, a sanitizer report, a leak,
# an input slower than 10 s or above 2 GiB of memory fails the run; libFuzzer writes the input to
# BUILD/artifacts/ (keep it under tests/fuzz/regressions/TARGET once fixed).
set -uo pipefail
build=${1:?usage: run.sh BUILD SECONDS TARGET...}
seconds=${2:?usage: run.sh BUILD SECONDS TARGET...}
shift 2
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$build/artifacts"
failed=()
for target in "$@"; do
  corpus="$build/corpus/$target"
  mkdir -p "$corpus"
  cp -n "$here/seeds/$target/"* "$corpus/" 2>/dev/null || true
  find "$here/regressions/$target" -type f ! -name README.md -exec cp -n {} "$corpus/" \; 2>/dev/null || true
  log="$build/fuzz_$target.log"
  start=$(date +%s)
  ASAN_OPTIONS=detect_leaks=1:allocator_may_return_null=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$build/tests/fuzz/fuzz_$target" "$corpus" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -max_len=262144 -artifact_prefix="$build/artifacts/$target-" -print_final_stats=1 >"$log" 2>&1
  status=$?
  runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  echo "fuzz_$target: exit $status after $(($(date +%s) - start)) s, $runs inputs, corpus $(ls "$corpus" | wc -l) files"
  if [ "$status" -ne 0 ]; then
    tail -n 40 "$log"
    failed+=("$target")
  fi
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "fuzzing found problems in: ${failed[*]} (inputs in $build/artifacts/)" >&2
  exit 1
fi
echo "fuzzing: no crash, leak or timeout in $# target(s), $seconds s each"
