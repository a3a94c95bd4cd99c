#!/usr/bin/env bash
# ctest mesh_shaders.lavapipe_backports: the tests that need VK_EXT_mesh_shader, run on the second
# lavapipe that `make test-deps` fetches (tests/drivers/fetch_lavapipe.sh), where they may not
# skip (STSV_REQUIRE_MESH_SHADERS=1 makes a missing extension a failure). First checks that the
# private driver is the one in use (`stsv info --json`: its one device, its version, mesh shaders),
# then runs the mesh-path tests and a `--validation` render through the mesh shader.
#
#   tests/drivers/mesh_shader_test.sh DRIVER_DIR STSV TEST_GPU TEST_GPU_RENDER
set -euo pipefail
driver_dir=$1 stsv=$2 test_gpu=$3 test_gpu_render=$4
manifest=$driver_dir/lvp_icd.json
if [ ! -f "$manifest" ] || [ ! -f "$driver_dir/version" ]; then
  echo "FAIL: the second lavapipe (Mesa from bookworm-backports, with VK_EXT_mesh_shader) is not in $driver_dir."
  echo "'make test-deps' fetches it (tests/drivers/fetch_lavapipe.sh $driver_dir); it needs deb.debian.org."
  exit 1
fi
export VK_DRIVER_FILES=$manifest STSV_REQUIRE_MESH_SHADERS=1
version=$(cat "$driver_dir/version")
upstream=${version%%-*}
"$stsv" info --json | python3 -c '
import json, sys
devices = json.load(sys.stdin)["vulkan"]["devices"]
upstream = sys.argv[1]
print("devices:", [(d["name"], d["driver"], d["mesh_shader"]) for d in devices])
assert len(devices) == 1, "VK_DRIVER_FILES should leave one device"
assert "Mesa " + upstream in devices[0]["driver"], "not the fetched lavapipe " + upstream
assert devices[0]["mesh_shader"], "the fetched lavapipe lacks VK_EXT_mesh_shader"
' "$upstream"
"$test_gpu" --gtest_filter='*MeshShader*'
"$test_gpu_render" --gtest_filter='*MeshShader*'
# Renders through the task and mesh shaders with validation on, every object-based method: no
# message.
log=$(mktemp)
trap 'rm -f "$log" "$log.png"' EXIT
for method in stsv dcs pw dcs+stsv pw+stsv; do
  "$stsv" render fence --method "$method" --extrusion mesh --validation --size 96x72 --samples 64 -q \
    -o "$log.png" 2> "$log"
  if grep -qi "validation\|VUID" "$log"; then
    cat "$log"
    echo "FAIL: validation messages on the mesh path of $method"
    exit 1
  fi
done
echo "mesh-shader tests passed on lavapipe $version"
