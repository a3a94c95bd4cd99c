#!/usr/bin/env bash
# The regression check in ctest: every method on every backend renders fence, foliage, knot and
# tests/data/scene/example.json at a fixed seed (bench/dump_ls_check.sh: 96x72, the knot 64x48, 64
# samples, bitmask and counter buffers), with Vulkan validation on, and each light-sample buffer
# of a per-sample method must be byte-identical to the one recorded for the machine's instruction
# set in tests/golden/ISA/sha256.txt (tests/golden/isa.sh).
#
#   tests/golden/golden_test.sh STSV SOURCE_DIR
#
# A change meant to alter results regenerates the records, and its commit says why:
#   PER_SAMPLE_ONLY=1 bench/dump_ls_check.sh record tests/golden/$(tests/golden/isa.sh) build/cli/stsv
set -uo pipefail
stsv=${1:?usage: golden_test.sh STSV SOURCE_DIR}
source=${2:?usage: golden_test.sh STSV SOURCE_DIR}
err=$(mktemp)
trap 'rm -f "$err"' EXIT
cd "$source" || exit 1
isa=$(bash tests/golden/isa.sh)
if [ ! -f "tests/golden/$isa/sha256.txt" ]; then
  echo "FAIL: no golden record for this machine's instruction set ($isa); record one on it after" >&2
  echo "checking with stsv compare that only boundary samples differ from another record:" >&2
  echo "  PER_SAMPLE_ONLY=1 bench/dump_ls_check.sh record tests/golden/$isa build/cli/stsv" >&2
  exit 1
fi
STSV_VALIDATION=1 PER_SAMPLE_ONLY=1 bash bench/dump_ls_check.sh compare "tests/golden/$isa" "$stsv" 2>"$err"
status=$?
if grep -q "vulkan validation" "$err"; then
  echo "FAIL: Vulkan validation messages:" >&2
  grep "vulkan validation" "$err" | sort | uniq -c | head -20 >&2
  exit 1
fi
if [ "$status" -ne 0 ]; then
  cat "$err" >&2
  echo "FAIL: the light-sample buffers above differ from tests/golden/$isa/sha256.txt (< recorded, > now)." >&2
  echo "If the change is meant to alter results, regenerate the records (one per instruction set:" >&2
  echo "Embree and lavapipe pick their kernels by CPU) and say why in the commit:" >&2
  echo "  PER_SAMPLE_ONLY=1 bench/dump_ls_check.sh record tests/golden/$isa build/cli/stsv" >&2
  exit 1
fi
echo "golden: every light-sample buffer as recorded for $isa"
