#include "tests/fuzz/fuzz_targets.h"

#include "core/error.h"
#include "core/image.h"
#include "core/memory_budget.h"
#include "render/cpu/cpu_renderer.h"
#include "sampling/ls_buffer.h"
#include "scene/load.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace stsv::fuzz {

namespace fs = std::filesystem;

namespace {

/// A directory of this process for the inputs, holding copies of the test data a scene may name
/// (grate.png, crate.obj, crate.mtl).
const fs::path& workDirectory() {
    static const fs::path dir = [] {
        fs::path d = fs::temp_directory_path() / ("stsv_fuzz_" + std::to_string(::getpid()));
        fs::create_directories(d);
        for (const char* name : {"grate.png", "crate.obj", "crate.mtl"})
            fs::copy_file(fs::path(STSV_TEST_DATA) / "scene" / name, d / name,
                          fs::copy_options::overwrite_existing);
        // Inputs may ask for anything; a loader must refuse what does not fit, not exhaust the
        // fuzzer's memory.
        setMemoryLimit(std::uint64_t(256) << 20);
        return d;
    }();
    return dir;
}

std::string write(const std::string& name, const char* data, std::size_t size) {
    std::string path = (workDirectory() / name).string();
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(data, static_cast<std::streamsize>(size));
    if (!out) throw std::runtime_error("fuzz harness: cannot write " + path);
    return path;
}

/// A scene a loader accepted goes on to a small frame on the CPU: the reference (Embree's
/// G-buffer and shadow rays, the texel rule in its filter), and DCS with STSV (the silhouettes,
/// the layer tree, STSV's projective lookup and the same texel rule). A valid file with an extreme
/// value crashes here, not in the loader.
void renderSmallFrames(const Scene& scene) {
    for (Method method : {Method::Reference, Method::DcsStsv}) {
        RenderOptions options;
        options.method = method;
        options.backend = Backend::Cpu;
        options.width = 8;
        options.height = 6;
        options.samples = 16;
        (void)makeCpuRenderer(scene, options)->render();
    }
}

} // namespace

const std::vector<std::string>& targetNames() {
    static const std::vector<std::string> names = {"json", "obj", "off", "png", "npy", "exr", "gltf"};
    return names;
}

void runTarget(const std::string& target, const std::uint8_t* data, std::size_t size) {
    const auto* text = reinterpret_cast<const char*>(data);
    try {
        if (target == "json") {
            renderSmallFrames(loadScene(write("input.json", text, size)));
        } else if (target == "obj") {
            const std::string input(text, size);
            const std::size_t split = input.find("\n#MTL\n");
            const std::string obj = input.substr(0, split);
            const std::string mtl = split == std::string::npos ? std::string() : input.substr(split + 6);
            write("m.mtl", mtl.data(), mtl.size());
            renderSmallFrames(loadScene(write("input.obj", obj.data(), obj.size())));
        } else if (target == "gltf") {
            // Binary glTF by its magic, else the JSON form; either may name grate.png beside it.
            const bool binary = size >= 4 && std::string(text, 4) == "glTF";
            renderSmallFrames(loadScene(write(binary ? "input.glb" : "input.gltf", text, size)));
        } else if (target == "off") {
            renderSmallFrames(loadScene(write("input.off", text, size)));
        } else if (target == "png") {
            (void)readPngRgba(write("input.png", text, size));
        } else if (target == "npy") {
            const std::string path = write("input.npy", text, size);
            (void)LightSampleBuffer::readNpy(path);
            (void)LightSampleBuffer::readNpy(path, BufferKind::Counters);
        } else if (target == "exr") {
            (void)readExr(write("input.exr", text, size));
        } else {
            throw std::invalid_argument("unknown fuzz target " + target);
        }
    } catch (const Error&) {
        // A clear refusal is the right answer to most fuzzed input.
    }
}

} // namespace stsv::fuzz
