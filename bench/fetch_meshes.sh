#!/usr/bin/env bash
# Fetches the real meshes of the `real-meshes` bench preset from Debian's archive (no other
# network) into DIR, default build/meshes:
#   2CylinderEngine.glb  Khronos glTF sample, 110 k triangles     (assimp-testmodels)
#   armadillo.off        Stanford scan, 52 k triangles              (libcgal-demo's data)
#   fandisk_large.off    CAD model, 32 k triangles                  (libcgal-demo's data)
#
#   bench/fetch_meshes.sh [DIR]
#
# `apt-get download` needs no root; the packages are unpacked in a temporary folder and only the
# three files are kept. A mesh already in DIR is not fetched again.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
dir=${1:-$root/build/meshes}
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
if [ -s "$dir/2CylinderEngine.glb" ] && [ -s "$dir/armadillo.off" ] && [ -s "$dir/fandisk_large.off" ]; then
  echo "meshes already in $dir"
  exit 0
fi
work=$(mktemp -d)
chmod 755 "$work" # apt-get download runs as _apt when root
trap 'rm -rf "$work"' EXIT
cd "$work"
echo "downloading assimp-testmodels and libcgal-demo from the Debian archive ..."
apt-get download assimp-testmodels libcgal-demo >/dev/null
for deb in ./*.deb; do dpkg-deb -x "$deb" unpacked; done
engine=$(find unpacked -name 2CylinderEngine.glb -path '*glTF-Binary*' | head -n 1)
[ -n "$engine" ] || { echo "fetch_meshes.sh: 2CylinderEngine.glb is not in assimp-testmodels" >&2; exit 1; }
cp "$engine" "$dir/2CylinderEngine.glb"
data=$(find unpacked -name data.tar.gz -path '*libcgal*' | head -n 1)
[ -n "$data" ] || { echo "fetch_meshes.sh: libcgal-demo holds no data.tar.gz" >&2; exit 1; }
tar -xzf "$data" -C "$work" data/meshes/armadillo.off data/meshes/fandisk_large.off
cp data/meshes/armadillo.off data/meshes/fandisk_large.off "$dir/"
echo "wrote $dir/2CylinderEngine.glb, armadillo.off, fandisk_large.off"
