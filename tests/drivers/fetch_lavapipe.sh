#!/usr/bin/env bash
# Fetches a second lavapipe, with VK_EXT_mesh_shader, for the mesh-shader tests, without touching
# the machine's Vulkan: Mesa's mesa-vulkan-drivers from Debian's bookworm-backports (Mesa 25),
# downloaded with a private apt configuration (its own sources list, package lists and cache
# under DEST/apt; the system's sources and state are never written), its lavapipe library
# extracted into DEST and an ICD manifest, DEST/lvp_icd.json, that points at it. Select it for
# any command or test with VK_DRIVER_FILES=DEST/lvp_icd.json.
#
#   tests/drivers/fetch_lavapipe.sh DEST
#
# A no-op when DEST already holds it. DEST/version records the package's version.
set -euo pipefail
dest=${1:?usage: fetch_lavapipe.sh DEST}
mkdir -p "$dest"
dest=$(cd "$dest" && pwd)
manifest=$dest/lvp_icd.json
library=$dest/libvulkan_lvp.so
if [ -f "$manifest" ] && [ -f "$library" ] && [ -f "$dest/version" ]; then
  exit 0
fi
apt_dir=$dest/apt
mkdir -p "$apt_dir/lists/partial" "$apt_dir/cache/archives/partial" "$apt_dir/download"
echo "deb [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://deb.debian.org/debian bookworm-backports main" \
  > "$apt_dir/sources.list"
apt_options=(-o "Dir::Etc::SourceList=$apt_dir/sources.list" -o Dir::Etc::SourceParts=/dev/null
             -o "Dir::State::Lists=$apt_dir/lists" -o "Dir::Cache=$apt_dir/cache" -o Debug::NoLocking=1
             -o APT::Sandbox::User=root -qq)
apt-get "${apt_options[@]}" update
(cd "$apt_dir/download" && rm -f ./*.deb && apt-get "${apt_options[@]}" download mesa-vulkan-drivers/bookworm-backports)
package=$(ls "$apt_dir"/download/mesa-vulkan-drivers_*.deb)
rm -rf "$apt_dir/extract"
dpkg-deb -x "$package" "$apt_dir/extract"
cp "$apt_dir/extract/usr/lib/x86_64-linux-gnu/libvulkan_lvp.so" "$library"
api=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["ICD"]["api_version"])' \
  "$apt_dir/extract/usr/share/vulkan/icd.d/lvp_icd.json")
printf '{\n  "file_format_version": "1.0.0",\n  "ICD": {"library_path": "%s", "api_version": "%s"}\n}\n' \
  "$library" "$api" > "$manifest"
dpkg-deb -f "$package" Version > "$dest/version"
rm -rf "$apt_dir/extract" "$apt_dir/download"
echo "lavapipe $(cat "$dest/version") in $dest (VK_DRIVER_FILES=$manifest)"
