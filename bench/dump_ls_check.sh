#!/usr/bin/env bash
# Behaviour check for changes that must not alter results: renders every method on every backend
# that implements it, on the built-in scenes fence, foliage and knot and on
# tests/data/scene/example.json, at a fixed seed, and writes each light-sample buffer (--dump-ls)
# with its SHA-256. Methods without per-sample bits (pw, pcf, ...) refuse --dump-ls; their
# float32 visibility (--visibility .npy) is checked instead.
#
#   bench/dump_ls_check.sh record DIR [STSV]    render and write DIR/sha256.txt
#   bench/dump_ls_check.sh compare DIR [STSV]   render again and compare with DIR/sha256.txt
#
# Record with the commit before a change, compare with the change: every file must be
# byte-identical. STSV defaults to build/cli/stsv. The methods and backends come from
# `stsv info --methods`, so a new method joins the check without editing this script.
# PER_SAMPLE_ONLY=1 leaves out the methods without per-sample bits: the float visibility of pw on
# Vulkan varies in its last bits from run to run (its wedges' coverage is summed by additive
# blending, in the order the compute passes append the hulls), so only integer buffers are
# byte-exact across runs (tests/golden uses this).
set -euo pipefail
mode=${1:?usage: dump_ls_check.sh record|compare DIR [STSV]}
dir=${2:?usage: dump_ls_check.sh record|compare DIR [STSV]}
stsv=${3:-build/cli/stsv}
here=$(cd "$(dirname "$0")/.." && pwd)

scenes=(fence foliage knot "$here/tests/data/scene/example.json")
# method backend pairs: from the method table where the binary has it, else the fixed list of
# the methods that existed before it.
if pairs=$("$stsv" info --methods 2>/dev/null); then :; else
  pairs=$(for m in reference stsv pw dcs pw+stsv dcs+stsv; do
    echo "$m cpu"; [ "$m" = reference ] || echo "$m vulkan"; done)
fi

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
while read -r method backend; do
  [ -n "$method" ] || continue
  for scene in "${scenes[@]}"; do
    name=$(basename "$scene" .json)
    # The knot is a mesh: its dense wedge passes are slow on lavapipe, so a smaller frame.
    size=96x72; [ "$name" = knot ] && size=64x48
    for buffer in bitmask counters; do
      file="$out/${name}_${method/+/_}_${backend}_${buffer}.npy"
      common=("$scene" --method "$method" --backend "$backend" --size "$size" --samples 64 --seed 7
        --buffer "$buffer" -q)
      if ! err=$("$stsv" render "${common[@]}" --dump-ls "$file" 2>&1); then
        case "$err" in
        *"no per-sample answer"*)
          [ "${PER_SAMPLE_ONLY:-0}" = 1 ] && continue
          "$stsv" render "${common[@]}" --visibility "${file%.npy}_visibility.npy" ;;
        *) echo "$err" >&2; exit 1 ;;
        esac
      elif [ -n "$err" ]; then
        echo "$err" >&2 # warnings, and validation messages under STSV_VALIDATION=1
      fi
    done
  done
done <<<"$pairs"
(cd "$out" && sha256sum -- *.npy) >"$out/sha256.txt"

case "$mode" in
record)
  mkdir -p "$dir"
  cp "$out/sha256.txt" "$dir/sha256.txt"
  echo "recorded $(wc -l <"$dir/sha256.txt") light-sample buffers in $dir/sha256.txt"
  ;;
compare)
  if diff <(sort -k2 "$dir/sha256.txt") <(sort -k2 "$out/sha256.txt"); then
    echo "identical: $(wc -l <"$out/sha256.txt") light-sample buffers"
  else
    echo "light-sample buffers differ (< recorded, > now)" >&2
    exit 1
  fi
  ;;
*)
  echo "unknown mode $mode (record or compare)" >&2
  exit 2
  ;;
esac
