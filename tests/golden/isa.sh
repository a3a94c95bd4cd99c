#!/usr/bin/env bash
# The instruction set the golden record of this machine is kept for: avx512 (what Embree 3 calls
# AVX512SKX: F, CD, DQ, BW and VL), else avx2, else sse. Embree and lavapipe pick their kernels by
# it, and a sample on a boundary may fall the other way from one to another.
flags=$(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null || true)
has() { for f in "$@"; do grep -qw "$f" <<<"$flags" || return 1; done; }
if has avx512f avx512cd avx512dq avx512bw avx512vl; then
  echo avx512
elif has avx2; then
  echo avx2
else
  echo sse
fi
