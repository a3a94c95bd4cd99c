#!/usr/bin/env bash
# The CPU backend needs no Vulkan: the CPU test program links no Vulkan code (checked against the
# Vulkan one, which must), the program links no Vulkan loader, and `--backend cpu` renders with
# no loader and with no driver, while `--backend vulkan` says what is missing.
#
#   cpu_without_vulkan_test.sh STSV TEST_RENDER TEST_GPU_RENDER
set -euo pipefail
stsv=$1 cpu_tests=$2 gpu_tests=$3
fail() { echo "FAIL: $*" >&2; exit 1; }
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT

# Vulkan code in a program: the loader's entry points, the device wrapper, glslang.
vulkan_symbols() { nm -C "$1" | grep -cE ' (vkCreateInstance|stsv::Device::Device|glslang::TShader::parse)' || true; }
[ "$(vulkan_symbols "$gpu_tests")" -gt 0 ] || fail "the check finds no Vulkan code in $gpu_tests, which has it"
[ "$(vulkan_symbols "$cpu_tests")" -eq 0 ] || fail "$cpu_tests links Vulkan code: $(nm -C "$cpu_tests" |
  grep -E ' (vkCreateInstance|stsv::Device::Device|glslang::TShader::parse)' | head -3)"
if readelf -d "$stsv" "$cpu_tests" | grep -E 'NEEDED.*libvulkan'; then fail "a program links the Vulkan loader"; fi

render() { "$stsv" render fence --size 32x24 --samples 16 "$@"; }
# No loader: the CPU renders, Vulkan names the loader it could not open.
STSV_VULKAN_LOADER="$scratch/libvulkan.so.1" render --backend cpu -o "$scratch/cpu.png" ||
  fail "--backend cpu failed without a Vulkan loader"
[ -s "$scratch/cpu.png" ] || fail "--backend cpu wrote no image without a Vulkan loader"
set +e
err=$(STSV_VULKAN_LOADER="$scratch/libvulkan.so.1" render --backend vulkan -o "$scratch/gpu.png" 2>&1)
code=$?
set -e
[ $code -eq 1 ] || fail "--backend vulkan without a loader exited $code, not 1: $err"
grep -q "cannot open the Vulkan loader $scratch/libvulkan.so.1" <<<"$err" || fail "no loader, unclear error: $err"
[ ! -e "$scratch/gpu.png" ] || fail "--backend vulkan wrote an image without a loader"

# No driver (the loader finds no ICD): the same.
nodriver=(env VK_ICD_FILENAMES="$scratch/none.json" VK_DRIVER_FILES="$scratch/none.json")
"${nodriver[@]}" "$stsv" render fence --size 32x24 --samples 16 --backend cpu -o "$scratch/cpu2.png" ||
  fail "--backend cpu failed without a Vulkan driver"
set +e
err=$("${nodriver[@]}" "$stsv" render fence --size 32x24 --samples 16 --backend vulkan -o "$scratch/gpu2.png" 2>&1)
code=$?
set -e
[ $code -eq 1 ] || fail "--backend vulkan without a driver exited $code, not 1: $err"
grep -q "no Vulkan driver was found" <<<"$err" || fail "no driver, unclear error: $err"
echo "ok: the CPU backend links and needs no Vulkan"
