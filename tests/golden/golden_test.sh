#!/usr/bin/env bash
# The regression check in ctest: every method on every backend renders fence, foliage, knot and
# tests/data/scene/example.json at a fixed seed (bench/dump_ls_check.sh: 96x72, the knot 64x48, 64
# samples, bitmask and counter buffers), with Vulkan validation on, and each light-sample buffer
# of a per-sample method must be byte-identical to the one recorded in tests/golden/sha256.txt.
#
#   tests/golden/golden_test.sh STSV SOURCE_DIR
#
# A change meant to alter results regenerates the record, and its commit says why:
#   PER_SAMPLE_ONLY=1 bench/dump_ls_check.sh record tests/golden build/cli/stsv
set -uo pipefail
stsv=${1:?usage: golden_test.sh STSV SOURCE_DIR}
source=${2:?usage: golden_test.sh STSV SOURCE_DIR}
err=$(mktemp)
trap 'rm -f "$err"' EXIT
cd "$source" || exit 1
STSV_VALIDATION=1 PER_SAMPLE_ONLY=1 bash bench/dump_ls_check.sh compare tests/golden "$stsv" 2>"$err"
status=$?
if grep -q "vulkan validation" "$err"; then
  echo "FAIL: Vulkan validation messages:" >&2
  grep "vulkan validation" "$err" | sort | uniq -c | head -20 >&2
  exit 1
fi
if [ "$status" -ne 0 ]; then
  cat "$err" >&2
  echo "FAIL: the light-sample buffers above differ from tests/golden/sha256.txt (< recorded, > now)." >&2
  echo "If the change is meant to alter results, regenerate the record and say why in the commit:" >&2
  echo "  PER_SAMPLE_ONLY=1 bench/dump_ls_check.sh record tests/golden build/cli/stsv" >&2
  echo "(The record is of this machine's instruction set: Embree and lavapipe pick their kernels by" >&2
  echo "CPU, and a sample on a boundary may fall the other way on another one.)" >&2
  exit 1
fi
echo "golden: every light-sample buffer as recorded"
