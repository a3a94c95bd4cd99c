#!/usr/bin/env bash
# The GPU measurements, in one run on a machine with a real GPU (README "Benchmarks on a GPU"):
#
#   bench/gpu_measure.sh STSV OUT [SECONDS]
#
# STSV is the program (the bundle's bin/stsv), OUT a folder for the results, SECONDS the time
# each step may take (default 150; a step that runs out is reported and the next one starts).
# Writes, each with the program's own output beside it as .txt:
#   info.json            stsv info --json: device, driver, mesh-shader support, version
#   fence-1024.json      --preset fence-1024 (GPU STSV against Embree on this machine's cores)
#   foliage-scale.json   --preset foliage-scale (1k to 64k S-triangles, 1024², with the check)
#   knot-scale.json      --preset knot-scale (11.5k to 184k triangles, dcs, with the check)
#   extrusion-SCENE-STAGE.json  stsv compare of the light-sample buffers of --extrusion hull (the
#                        default) and, where the device has VK_EXT_mesh_shader, mesh (the task and
#                        mesh shaders' hulls) against the geometry shader's prisms, bit by bit, on
#                        fence and foliage (stsv) and the knot (dcs), 1024², 64 samples; each
#                        render's --stats (fragments, frame time) beside them
#   extrusions-foliage.json, extrusions-knot.json  stsv bench through every extrusion the device
#                        offers in one run: stsv on foliage (1k, 4k, 16k S-triangles) and dcs on
#                        the knot, 1024², 64 samples, with the fragment counts
#   summary.txt          the table lines of every step and its exit status
# It stops at nothing: every step runs, and the script exits non-zero if any failed.
set -uo pipefail
stsv=${1:?usage: gpu_measure.sh STSV OUT [SECONDS]}
out=${2:?usage: gpu_measure.sh STSV OUT [SECONDS]}
limit=${3:-150}
mkdir -p "$out"
summary="$out/summary.txt"
: >"$summary"
failed=0

# step NAME COMMAND...: runs COMMAND under the time limit, output to OUT/NAME.txt.
step() {
  local name=$1
  shift
  local start=$SECONDS
  timeout --kill-after=10 "$limit" "$@" >"$out/$name.txt" 2>&1
  local rc=$?
  {
    echo "== $name: exit $rc after $((SECONDS - start)) s"
    # The bench's table rows and check columns; compare's error lines.
    grep -E '^[a-z].* (vulkan|cpu)[/ ]|identical|differ|error' "$out/$name.txt" | head -40
  } >>"$summary"
  [ "$rc" = 0 ] || failed=1
}

step info "$stsv" info --json
cp "$out/info.txt" "$out/info.json"
"$stsv" info 2>&1 | sed -n '/^cpu threads/,$p' >>"$summary"

for preset in fence-1024 foliage-scale knot-scale; do
  step "$preset" "$stsv" bench --preset "$preset" --json "$out/$preset.json" -q
done

stages="geometry hull"
if grep -q '"mesh_shader": *true' "$out/info.json"; then
  stages="$stages mesh"
else
  echo "== extrusion: the device has no VK_EXT_mesh_shader; the mesh-shader path was not run" >>"$summary"
fi
step extrusions-foliage "$stsv" bench foliage --methods stsv --backends vulkan --vary count=250,1000,4000 \
  --size 1024x1024 --samples 64 --extrusion "${stages// /,}" --json "$out/extrusions-foliage.json" -q
step extrusions-knot "$stsv" bench knot --methods dcs --backends vulkan --size 1024x1024 --samples 64 \
  --extrusion "${stages// /,}" --json "$out/extrusions-knot.json" -q
for scene in fence foliage knot; do
  method=stsv
  [ "$scene" = knot ] && method=dcs
  for stage in $stages; do
    step "render-$scene-$stage" "$stsv" render "$scene" --method "$method" --size 1024x1024 --samples 64 -q \
      --extrusion "$stage" --dump-ls "$out/$scene-$stage.npy" --stats "$out/$scene-$stage-stats.json"
  done
  for stage in $stages; do
    [ "$stage" = geometry ] && continue
    step "extrusion-$scene-$stage" "$stsv" compare "$out/$scene-geometry.npy" "$out/$scene-$stage.npy" \
      --json "$out/extrusion-$scene-$stage.json"
  done
  for stage in $stages; do rm -f "$out/$scene-$stage.npy"; done
done

cat "$summary"
exit $failed
