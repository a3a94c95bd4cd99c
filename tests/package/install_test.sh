#!/usr/bin/env bash
# The installed package as a user of another project sees it: `cmake --install` into a fresh
# prefix; its layout; the installed shaders compiled on their own; the math headers compiled with
# Vulkan out of reach; a separate CMake project that finds the package and checks the projective
# transmittance lookup; and the installed program rendering from a moved copy of the prefix.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR
source "$(dirname "$0")/common.sh"
build=$(realpath "$1")
source=$(realpath "$2")
prefix=$work/prefix

cmake --install "$build" --prefix "$prefix" >/dev/null
for f in bin/stsv lib/libstsv_volumes.a lib/libstsv_render.a include/stsv/volumes/stsv_dh.h include/stsv/core/dh.h \
    include/stsv/render/methods.h lib/cmake/stsv/stsvConfig.cmake lib/cmake/stsv/stsvConfigVersion.cmake \
    lib/cmake/stsv/stsvTargets.cmake share/stsv/shaders/volumes/shaders/stsv.frag share/stsv/shaders/render/shaders/frame_bindings.glsl \
    share/stsv/shaders/volumes/stsv_dh.h share/stsv/shaders/core/dh.h share/doc/stsv/README.md \
    share/doc/stsv/LICENSE share/doc/stsv/docs/user-guide.md share/doc/stsv/docs/demo.png; do
    [[ -f $prefix/$f ]] || fail "cmake --install wrote no $f"
done

# The installed shader folder stands alone: every entry point (in its family's folder) compiles
# with it as the only include path, as in an engine that lifts it.
shaders=$prefix/share/stsv/shaders
count=0
for s in "$shaders"/*/shaders/*.{vert,geom,frag,comp,mesh,task}; do
    [[ -e $s ]] || continue
    glslangValidator -V --target-env vulkan1.3 -I"$shaders" -o "$work/s.spv" "$s" >"$work/glslang.log" 2>&1 ||
        fail "installed $s does not compile on its own: $(cat "$work/glslang.log")"
    count=$((count + 1))
done
((count >= 15)) || fail "only $count shader entry points installed"
echo "$count installed shaders compile with -I share/stsv/shaders alone"

# The math headers need no Vulkan: with a vulkan/vulkan.h that stops the compiler first on the
# include path, every header of the math modules still compiles. (Headers that #error until their
# includer defines a data accessor, as resolve_dh.h, are left to the sources that include them.)
mkdir -p "$work/novulkan/vulkan"
echo '#error "a math header includes Vulkan"' >"$work/novulkan/vulkan/vulkan.h"
: >"$work/math.cpp"
for h in "$prefix"/include/stsv/{core,scene,sampling,volumes,wedges,shadowmaps}/*.h; do
    grep -q '#error' "$h" && continue
    echo "#include \"${h#"$prefix"/include/stsv/}\"" >>"$work/math.cpp"
done
c++ -std=c++20 -fsyntax-only -DGLM_FORCE_XYZW_ONLY -DGLM_ENABLE_EXPERIMENTAL -I"$work/novulkan" \
    -I"$prefix/include/stsv" "$work/math.cpp" 2>"$work/math.log" || fail "math headers: $(head -20 "$work/math.log")"
echo "$(wc -l <"$work/math.cpp") math headers compile without Vulkan"

# A separate project: find_package(stsv CONFIG), link stsv::volumes, check Eq. 1-5 on known cases;
# and link every exported library, rendering a frame through them.
cmake -S "$source/tests/package/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$prefix" \
    -DCMAKE_BUILD_TYPE=Release >"$work/consumer.log" 2>&1 || fail "configuring the consumer: $(cat "$work/consumer.log")"
cmake --build "$work/consumer" >>"$work/consumer.log" 2>&1 || fail "building the consumer: $(cat "$work/consumer.log")"
"$work/consumer/consumer" || fail "the consumer's checks failed"
"$work/consumer/consumer_all" || fail "the consumer of every exported library failed"

# The program from a moved copy of the prefix: nothing points back at where it was installed.
mkdir -p "$work/elsewhere"
mv "$prefix" "$work/elsewhere/stsv"
program=$work/elsewhere/stsv/bin/stsv
check_no_checkout_path "$program" "$source"
# (Read whole before matching: grep -q stops reading at the first match, and under pipefail the
# writer's SIGPIPE would fail the pipeline.)
info_json=$(env -u STSV_SHADER_DIR "$program" info --json) || fail "stsv info --json failed"
grep -q '"embedded": true' <<<"$info_json" || fail "stsv info: the shaders are not embedded"
render_fence "$program" "$source" "$build"
echo "installed stsv renders fence from $work/elsewhere"
