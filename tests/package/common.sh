# Shared by the package tests (sourced): scratch folder, failure, and running an installed stsv
# the way a user on another machine would.
set -euo pipefail

work=$(mktemp -d "${TMPDIR:-/tmp}/stsv_package_test.XXXXXX")
trap 'rm -rf "$work"' EXIT

fail() {
    echo "FAIL: $*" >&2
    exit 1
}

# check_no_checkout_path PROGRAM SOURCE: the program, without its debug information, names no path
# of the checkout it was built from (so nothing in it can read shaders or data from there).
check_no_checkout_path() {
    objcopy --strip-debug "$1" "$work/stripped"
    if grep -aqF "$2" "$work/stripped"; then
        fail "$1 holds the checkout path $2: $(grep -aoF "$2[^[:space:]]*" "$work/stripped" | head -3 | tr '\n' ' ')"
    fi
}

# render_fence PROGRAM SOURCE BUILD: `stsv render fence --size 64x64` with validation layers, from a
# folder outside the checkout, without STSV_SHADER_DIR or LD_LIBRARY_PATH, and where the kernel
# lets an unprivileged user have a mount namespace, with the checkout and the build tree hidden
# under empty folders. Leaves fence.png, stats.json and err.txt in $work/run.
render_fence() {
    local program=$1 source=$2 build=$3
    mkdir -p "$work/run"
    cd "$work/run"
    local render=(env -u STSV_SHADER_DIR -u LD_LIBRARY_PATH "$program" render fence --size 64x64 --validation -q
        -o fence.png --stats stats.json)
    mkdir -p "$work/probe"
    if unshare -rm mount -t tmpfs none "$work/probe" 2>/dev/null; then
        echo "rendering with $source and $build hidden"
        # shellcheck disable=SC2016
        unshare -rm bash -c 'for d in "$1" "$2"; do mount -t tmpfs none "$d"; done
            [ -z "$(ls -A "$1")" ] || exit 90
            shift 2; exec "$@"' hide "$source" "$build" "${render[@]}" 2>err.txt ||
            fail "render with the checkout hidden exited $?: $(cat err.txt)"
    else
        echo "no unprivileged mount namespace here: the checkout stays reachable (the program is checked to name none of its paths)"
        "${render[@]}" 2>err.txt || fail "render exited $?: $(cat err.txt)"
    fi
    [[ -s fence.png ]] || fail "render wrote no fence.png"
    if grep -q "vulkan validation" err.txt; then fail "validation messages: $(cat err.txt)"; fi
    local version
    version=$("$program" --version)
    grep -qF "\"version\": \"${version#stsv }\"" stats.json || fail "stats.json lacks the version ${version#stsv }"
}
