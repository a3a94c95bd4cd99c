#!/usr/bin/env bash
# Runs the measurements docs/measurements.md shows and writes their --json files to
# bench/results/, then regenerates the document's tables from them (bench/tables.py update).
#
#   bench/measure.sh [NAME...]     (no NAME: all of them; STSV=path/to/stsv to use another binary)
#
# Each measurement is one stsv command; its file records the command, the stsv version (the
# commit) and the machine (the Vulkan driver too: the *-mesa25 ones select the second lavapipe).
# Commit the files with the document: the tables are never edited by hand, and
# `bench/tables.py check docs/measurements.md` (run by the test suite) fails when a table does not
# match its file.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
stsv=${STSV:-$root/build/cli/stsv}
cd "$root" # the commands, recorded in the files, name paths relative to the repository
results=bench/results
mkdir -p "$results"

every_method="stsv/vulkan,stsv/cpu,dcs+stsv/vulkan,dcs+stsv/cpu,pw+stsv/vulkan,pw+stsv/cpu"
opaque_methods="stsv/vulkan,stsv/cpu,dcs/vulkan,dcs/cpu,pw/vulkan,pw/cpu"
all_methods="stsv,pw,dcs,pw+stsv,dcs+stsv,pcf,pcss,vsm,esm,evsm,msm,csm,peel"
example=tests/data/scene/example.json
# The fairness sweep: every image-based method's knobs tuned on each scene of the tuning set alone
# (bench/tables.py tune: the defaults' error beside each scene's best).
map_methods="pcf,pcss,vsm,esm,evsm,msm,csm,peel,avsm,vpcss"
tune_options="--size 160x120 --samples 64 --converged 8 -q"
declare -A tune_scenes=([fence]=fence [foliage]=foliage [knot]=knot [fencemesh]=fence-mesh
  [particlesinside]="particles --set height=0.9 --buffer transmittance" [example]=$example
  [planes]=tests/data/scene/parallel_planes.json [planestwo]=tests/data/scene/parallel_planes_two.json)
tune_all=()
for key in fence foliage knot fencemesh particlesinside example planes planestwo; do
  for method in ${map_methods//,/ }; do tune_all+=("tune-$key-$method"); done
done

# The defaults nearest every scene's own best at once (tune --objective worst) for the methods
# whose defaults miss 1.25x somewhere, on the scenes whose bests pull apart (a subset: its least
# worst ratio is a lower bound for the whole set's).
declare -A worst_scenes=([pcf]="foliage planes" [pcss]="foliage planes" [vsm]="foliage planes"
  [evsm]="foliage planes" [msm]="foliage example planes" [csm]="foliage example planes"
  [esm]="example foliage" [vpcss]="foliage planes")
worst_all=()
for method in pcf pcss vpcss vsm evsm msm esm csm; do worst_all+=("worst-$method"); done

# name, then the stsv arguments (the --json file is added).
measurement() {
  case $1 in
    compare-fence) echo compare fence --methods "$every_method" --size 256x192 --samples 64 ;;
    compare-foliage) echo compare foliage --methods "$every_method" --size 256x192 --samples 64 ;;
    compare-example) echo compare "$example" --methods "$every_method" --size 256x192 --samples 64 ;;
    compare-knot) echo compare knot --methods "$opaque_methods" --size 256x192 --samples 64 ;;
    bench-fence-1024) echo bench --preset fence-1024 ;;
    bench-knot-methods) echo bench --preset knot-methods ;;
    bench-baselines) echo bench --preset baselines ;;
    converged-fence) echo compare fence --methods "$all_methods" --converged 16 --size 512x512 ;;
    converged-foliage) echo compare foliage --methods "$all_methods" --converged 16 --size 512x512 ;;
    converged-knot) echo compare knot --methods "$all_methods" --converged 16 --size 512x512 ;;
    converged-example) echo compare "$example" --methods "$all_methods" --converged 16 --size 512x512 ;;
    sheet-fence) echo compare fence --methods "$all_methods" --converged 16 --size 192x144 \
      --sheet docs/fence-sheet.png ;;
    bench-fence-vs-mesh) echo bench --preset fence-vs-mesh ;;
    bench-foliage-count) echo bench foliage --methods stsv,reference --backends vulkan,cpu \
      --vary count=250,1000,4000 --size 512x512 --samples 64 --repeat 3 --check ;;
    bench-knot-scale) echo bench --preset knot-scale ;;
    bench-real-meshes) echo bench --preset real-meshes ;;
    bench-real-meshes-1024) echo bench --preset real-meshes --size 1024x768 --repeat 2 ;;
    bench-foliage-dense) echo bench foliage --methods stsv,reference --backends vulkan,cpu --vary count=4000,16000 \
      --size 1024x1024 --samples 64 --repeat 2 --check ;;
    compare-particles) echo compare particles --buffer transmittance --methods "$every_method" --size 256x192 \
      --samples 64 ;;
    sheet-particles) echo compare particles --buffer transmittance --methods "$all_methods,avsm,vpcss" --converged 16 \
      --size 192x144 --sheet docs/particles-sheet.png ;;
    bench-particles) echo bench --preset particles --repeat 1 --warmup 0 ;;
    bench-particles-maps) echo bench particles --methods avsm,vpcss --backends vulkan,cpu --vary count=1000,10000 \
      --size 1024x1024 --samples 64 --repeat 1 --warmup 1 ;;
    extrusion-hull-mesa22) echo bench foliage --methods stsv --backends vulkan --vary count=250,1000,4000 \
      --size 512x512 --samples 64 --repeat 3 --extrusion hull ;;
    extrusion-foliage-mesa25) echo bench foliage --methods stsv --backends vulkan --vary count=250,1000,4000 \
      --size 512x512 --samples 64 --repeat 3 --extrusion hull,mesh,geometry ;;
    extrusion-knot-mesa25) echo bench knot --methods dcs --backends vulkan --size 512x512 --samples 64 --repeat 3 \
      --extrusion hull,mesh,geometry ;;
    facing-knot) echo compare knot --backend cpu --methods stsv,pw,dcs,pcf,pcss,vsm,esm,evsm,msm,csm,peel \
      --converged 16 --size 256x256 --samples 64 ;;
    sheet-fabric) echo compare fence --set fabric=0.6 --buffer transmittance --methods "$all_methods,avsm,vpcss" \
      --converged 16 --size 192x144 --sheet docs/fabric-sheet.png ;;
    tune-*) # tune-SCENE-METHOD: one method tuned on one scene of the tuning set
      local key=${1#tune-} method=${1##*-}
      key=${key%-*}
      local scene=${tune_scenes[$key]:-}
      [ -n "$scene" ] && [[ ",$map_methods," == *",$method,"* ]] || return 1
      # shellcheck disable=SC2086 # the scene's options hold no spaces
      echo tune "$method" --scenes $scene $tune_options ;;
    worst-*) # worst-METHOD: tune --objective worst on the scenes of worst_scenes
      local method=${1#worst-} keys specs="" key
      keys=${worst_scenes[$method]:-}
      [ -n "$keys" ] || return 1
      for key in $keys; do specs+=" ${tune_scenes[$key]}"; done
      # shellcheck disable=SC2086 # scene names hold no spaces
      echo tune "$method" --scenes $specs --objective worst $tune_options ;;
    *) return 1 ;;
  esac
}
all=(compare-fence compare-foliage compare-example compare-knot bench-fence-1024 bench-knot-methods
     bench-baselines converged-fence converged-foliage converged-knot converged-example sheet-fence
     bench-fence-vs-mesh bench-foliage-count bench-knot-scale bench-real-meshes bench-real-meshes-1024 bench-foliage-dense compare-particles sheet-particles bench-particles
     bench-particles-maps sheet-fabric facing-knot extrusion-hull-mesa22 extrusion-foliage-mesa25 extrusion-knot-mesa25
     "${tune_all[@]}" "${worst_all[@]}")

names=("$@")
[ ${#names[@]} -gt 0 ] || names=("${all[@]}")
for name in "${names[@]}"; do
  if ! args=$(measurement "$name"); then
    echo "measure.sh: unknown measurement '$name' (known: ${all[*]})" >&2
    exit 2
  fi
  # The *-mesa25 measurements run on the second lavapipe that `make test-deps` fetches
  # (docs/developer.md#two-lavapipes); the others on the system's driver.
  case $name in
    *-mesa25) export VK_DRIVER_FILES=$root/build/drivers/lavapipe-backports/lvp_icd.json ;;
    *) unset VK_DRIVER_FILES ;;
  esac
  echo "== $name: stsv $args${VK_DRIVER_FILES:+ (VK_DRIVER_FILES=$VK_DRIVER_FILES)}"
  start=$(date +%s)
  # shellcheck disable=SC2086 # the arguments hold no spaces
  "$stsv" $args --json "$results/$name.json"
  echo "== $name: $(($(date +%s) - start)) s"
done
python3 bench/tables.py update docs/measurements.md
