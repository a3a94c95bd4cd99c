#!/usr/bin/env bash
# The relocatable bundle (`make bundle`, cmake/Bundle.cmake) as a user on another machine gets it:
# unpacked into a fresh folder, its libraries found through the program's $ORIGIN run path and no
# LD_LIBRARY_PATH, then `stsv info` and a render of fence from there.
# Usage: bundle_test.sh BUILD_DIR SOURCE_DIR
source "$(dirname "$0")/common.sh"
build=$(realpath "$1")
source=$(realpath "$2")
version=$("$build/cli/stsv" --version)
version=${version#stsv }
name=stsv-$version-linux-$(uname -m)

cmake -DBUILD_DIR="$build" -DOUTPUT_DIR="$work/dist" -P "$source/cmake/Bundle.cmake" >"$work/bundle.log" 2>&1 ||
    fail "Bundle.cmake: $(cat "$work/bundle.log")"
cat "$work/bundle.log"
[[ -f $work/dist/$name.tar.gz ]] || fail "no $name.tar.gz in: $(ls "$work/dist")"
mkdir -p "$work/fresh"
tar xzf "$work/dist/$name.tar.gz" -C "$work/fresh"
root=$work/fresh/$name
[[ -d $root ]] || fail "the archive holds no folder $name: $(ls "$work/fresh")"

for f in bin/stsv README.md LICENSE docs/user-guide.md docs/demo.png share/stsv/shaders/volumes/shaders/stsv.frag share/stsv/shaders/volumes/stsv_dh.h \
    lib/libembree3.so.3 lib/libtbb.so.12 lib/libOpenMeshCore.so.9.0 lib/libstdc++.so.6 lib/libgcc_s.so.1; do
    [[ -e $root/$f ]] || fail "the bundle lacks $f"
done
for f in "$root"/lib/libc.so* "$root"/lib/libm.so* "$root"/lib/libvulkan.so*; do
    [[ ! -e $f ]] || fail "the bundle holds $f, which the target machine provides"
done
[[ ! -e $root/include && ! -e $root/lib/cmake ]] || fail "the bundle holds the development files"

# The run path: DT_RPATH $ORIGIN/../lib (searched for the bundled libraries' own needs too).
readelf -d "$root/bin/stsv" | grep 'Library rpath: \[\$ORIGIN/../lib\]' >/dev/null ||
    fail "bin/stsv has no DT_RPATH \$ORIGIN/../lib: $(readelf -d "$root/bin/stsv" | grep -i path)"
# Every library the loader looks up resolves into lib/, but the C library family and the loader.
while read -r library _ resolved _; do
    [[ $resolved == /* ]] || continue
    case $library in
    libc.so.* | libm.so.* | libdl.so.* | libpthread.so.* | librt.so.* | libvulkan.so.*) continue ;;
    esac
    [[ $(realpath "$resolved") == "$(realpath "$root/lib")"/* ]] || fail "$library resolves to $resolved, outside the bundle"
done < <(env -u LD_LIBRARY_PATH ldd "$root/bin/stsv" | grep '=>')

mkdir -p "$work/run"
cd "$work/run"
env -u STSV_SHADER_DIR -u LD_LIBRARY_PATH "$root/bin/stsv" info >info.txt 2>&1 || fail "stsv info: $(cat info.txt)"
grep -q "^stsv $version" info.txt || fail "stsv info does not name version $version: $(head -1 info.txt)"
grep -q "^shaders: embedded" info.txt || fail "stsv info: the shaders are not embedded"
check_no_checkout_path "$root/bin/stsv" "$source"
render_fence "$root/bin/stsv" "$source" "$build"
echo "the bundle renders fence from $root"
