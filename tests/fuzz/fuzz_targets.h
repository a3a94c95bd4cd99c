// The loaders under fuzzing, one entry point each: libFuzzer drives them (tests/fuzz/libfuzzer/,
// `make fuzz`), and the normal test suite replays every seed and every input that ever crashed
// through the same functions (regression_test.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace stsv::fuzz {

/// The fuzzed loaders: "json" (a JSON scene, with the test data's textures and meshes beside
/// it), "obj" (an OBJ; after a line "#MTL" the rest is its material library m.mtl), "off",
/// "png", "npy" (a light-sample buffer), "exr" (an OpenEXR image, as compare reads visibilities),
/// "gltf" (a .glb when it starts with the binary magic "glTF", else a .gltf; images beside it as
/// for "json").
const std::vector<std::string>& targetNames();

/// Feeds `data` to the loader of `target`. Returns normally when the loader accepted the input
/// or refused it with stsv::Error; anything else (another exception, a crash, a sanitizer
/// report) is a bug the caller reports.
void runTarget(const std::string& target, const std::uint8_t* data, std::size_t size);

} // namespace stsv::fuzz
