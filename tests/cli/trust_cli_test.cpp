// Hostile and malformed input, failing writes and answers a method does not have: every case
// ends in one clear line and a non-zero exit, never a crash, a silent wrong picture or a file
// that lies. Each case here once crashed, exited 0 with a wrong result, or gave a message a user
// could not act on.
#include "cli_test_util.h"

#include "core/image.h"
#include "core/memory_budget.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

namespace stsv::test {
namespace {

namespace fs = std::filesystem;

/// CRC-32 of PNG chunks (ISO 3309, polynomial 0xedb88320), bit by bit.
std::uint32_t crc32Of(const std::string& bytes) {
    std::uint32_t crc = 0xffffffffu;
    for (unsigned char b : bytes) {
        crc ^= b;
        for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
    }
    return crc ^ 0xffffffffu;
}

std::string pngChunk(const std::string& type, const std::string& data) {
    auto be32 = [](std::uint32_t v) {
        return std::string{char(v >> 24), char((v >> 16) & 0xff), char((v >> 8) & 0xff), char(v & 0xff)};
    };
    const std::string body = type + data;
    return be32(std::uint32_t(data.size())) + body + be32(crc32Of(body));
}

/// A PNG with a valid header (8-bit RGBA of the given size) whose pixel data is `idat`.
std::string pngWith(std::uint32_t width, std::uint32_t height, const std::string& idat) {
    auto be32 = [](std::uint32_t v) {
        return std::string{char(v >> 24), char((v >> 16) & 0xff), char((v >> 8) & 0xff), char(v & 0xff)};
    };
    const std::string ihdr = be32(width) + be32(height) + std::string{8, 6, 0, 0, 0};
    return std::string("\x89PNG\r\n\x1a\n", 8) + pngChunk("IHDR", ihdr) + pngChunk("IDAT", idat) +
           pngChunk("IEND", "");
}

/// zlib header 78 9c, then 50 bytes of ff: the stream stb cannot inflate (it crashed the loader).
std::string corruptZlib() {
    return std::string("\x78\x9c", 2) + std::string(50, '\xff');
}

const char* const LIGHT_JSON =
    R"({"type": "rectangle", "position": [0, 3, 0], "normal": [0, -1, 0], "size": [1, 1], "radiance": [1, 1, 1]})";

/// A one-quad JSON scene whose material and camera are `material` and `camera` (JSON text).
std::string jsonScene(const std::string& material, const std::string& extraTop = "") {
    return R"({"materials": [)" + material +
           R"(], "meshes": [{"quad": {"size": [1, 1]}, "material": "m"}], "lights": [)" + LIGHT_JSON + "]" +
           extraTop + "}";
}

/// Whether `text` is valid UTF-8 (what a terminal shows as text).
bool isUtf8Text(const std::string& text) {
    for (std::size_t i = 0; i < text.size();) {
        const auto c = static_cast<unsigned char>(text[i]);
        const std::size_t n = c < 0x80           ? 1
                              : (c >> 5) == 0x6  ? 2
                              : (c >> 4) == 0xe  ? 3
                              : (c >> 3) == 0x1e ? 4
                                                 : 0;
        if (n == 0 || i + n > text.size()) return false;
        for (std::size_t k = 1; k < n; ++k)
            if ((static_cast<unsigned char>(text[i + k]) & 0xc0) != 0x80) return false;
        i += n;
    }
    return true;
}

struct Case {
    std::string name;
    std::vector<std::string> args;
    std::string expected; ///< text the one-line message must contain
};

void expectOneLineError(const Case& c, int expectedCode = 1) {
    std::vector<std::string> args = c.args;
    args.push_back("-q");
    const CliResult r = runStsv(args);
    EXPECT_EQ(r.code, expectedCode) << c.name << "\n" << describe(args, r);
    EXPECT_NE(r.err.find(c.expected), std::string::npos)
        << c.name << ": the message should say '" << c.expected << "'\n"
        << describe(args, r);
    EXPECT_EQ(r.err.rfind("stsv: error: ", 0), 0u) << c.name << "\n" << describe(args, r);
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << c.name << "\n" << describe(args, r);
    for (unsigned char ch : r.err)
        EXPECT_TRUE(ch == '\n' || (ch >= 0x20 && ch < 0x7f) || isUtf8Text(r.err))
            << c.name << ": byte " << int(ch) << " in the message";
    EXPECT_TRUE(isUtf8Text(r.err)) << c.name << ": the message is not UTF-8 text";
    EXPECT_LT(r.err.size(), 600u) << c.name << ": a message a terminal can show";
}

TEST(TrustCli, MalformedAndHostileInputsGiveOneClearLine) {
    ScratchDir dir;
    writeText(dir.file("corrupt.png"), pngWith(8, 8, corruptZlib()));
    writeText(dir.file("huge.png"), pngWith(20000, 20000, corruptZlib()));
    writeText(dir.file("png_texture.json"), jsonScene(R"({"name": "m", "alphaTexture": "corrupt.png"})"));
    writeText(dir.file("huge_texture.json"), jsonScene(R"({"name": "m", "alphaTexture": "huge.png"})"));
    writeText(dir.file("device_texture.json"), jsonScene(R"({"name": "m", "alphaTexture": "/dev/zero"})"));
    writeText(dir.file("dir_texture.json"), jsonScene(R"({"name": "m", "alphaTexture": "."})"));
    writeText(dir.file("corrupt.mtl"), "newmtl m\nKd 0.5 0.5 0.5\nmap_d corrupt.png\n");
    writeText(
        dir.file("corrupt_mtl.obj"),
        "mtllib corrupt.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nusemtl m\nf 1/1 2/2 3/3\n");
    writeText(dir.file("bright.mtl"), "newmtl m\nKd 5 5 5\n");
    writeText(dir.file("bright.obj"), "mtllib bright.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n");
    // 70 000 levels of nesting in three places a scene may hold a value.
    const std::string deep = std::string(70000, '[') + std::string(70000, ']');
    writeText(dir.file("deep_description.json"), R"({"description": )" + deep + "}");
    writeText(dir.file("deep_meshes.json"), R"({"meshes": )" + deep + "}");
    writeText(dir.file("deep_albedo.json"), jsonScene(R"({"name": "m", "albedo": )" + deep + "}"));
    writeText(dir.file("far_camera.json"),
              jsonScene(R"({"name": "m"})", R"(, "camera": {"eye": [1e25, 0, 0], "target": [0, 0, 0]})"));
    std::string lights;
    for (int i = 0; i < 1500; ++i) lights += std::string(i ? "," : "") + LIGHT_JSON;
    writeText(
        dir.file("many_lights.json"),
        R"({"materials": [{"name": "m"}], "meshes": [{"quad": {"size": [1, 1]}, "material": "m"}], "lights": [)" +
            lights + "]}");
    writeText(dir.file("garbage.obj"), std::string("\x01\x02\x03\xff\xfe garbage\n\0", 15));
    fs::create_directories(dir.file("folder.json"));
    writeText(dir.file("long_token.obj"), "v " + std::string(1000000, '1') + " 0 0\n");
    std::string utf16 = "\xff\xfe";
    for (char ch : std::string(R"({"meshes": []})")) utf16 += std::string{ch, '\0'};
    writeText(dir.file("utf16.json"), utf16);

    const std::vector<Case> cases = {
        {"corrupt PNG named by a JSON alphaTexture",
         {"render", dir.file("png_texture.json")},
         "pixel data is corrupt"},
        {"corrupt PNG named by an MTL map_d", {"render", dir.file("corrupt_mtl.obj")}, "corrupt.png"},
        {"PNG declaring 20000x20000", {"render", dir.file("huge_texture.json")}, "20000x20000"},
        {"a device as a texture", {"render", dir.file("device_texture.json")}, "device"},
        {"a directory as a texture", {"render", dir.file("dir_texture.json")}, "directory"},
        {"a directory as the scene", {"render", dir.file("folder.json")}, "directory"},
        {"deep JSON in description", {"render", dir.file("deep_description.json")}, "nested deeper than 64"},
        {"deep JSON in meshes", {"render", dir.file("deep_meshes.json")}, "nested deeper than 64"},
        {"deep JSON in albedo", {"render", dir.file("deep_albedo.json")}, "nested deeper than 64"},
        {"a camera 1e25 m away", {"render", dir.file("far_camera.json")}, "camera.eye"},
        {"an MTL Kd of 5, as a JSON albedo of 5 is",
         {"render", dir.file("bright.obj")},
         "'Kd' components must be"},
        {"1500 lights", {"render", dir.file("many_lights.json")}, "1500 lights"},
        {"binary garbage as OBJ", {"render", dir.file("garbage.obj")}, "garbage.obj"},
        {"a megabyte-long number", {"render", dir.file("long_token.obj")}, "malformed number"},
        {"a UTF-16 JSON file", {"render", dir.file("utf16.json")}, "invalid JSON"},
        {"a knot above the narrowed knob range",
         {"render", "knot", "--set", "segments=100000"},
         "[3, 20000]"},
        {"a knot above the memory limit",
         {"render", "knot", "--set", "segments=20000", "--set", "sides=200", "--max-memory", "4G"},
         "memory limit"},
        {"a frame above --max-memory",
         {"render", "fence", "--size", "64x64", "--max-memory", "1K"},
         "1.0 KiB"},
        {"a nonsense --max-memory", {"render", "fence", "--max-memory", "lots"}, "lots"},
    };
    for (const Case& c : cases) expectOneLineError(c);
}

TEST(TrustCli, OutputsAreWrittenInTheFormatTheirNameSaysOrRefused) {
    ScratchDir dir;
    const std::vector<Case> cases = {
        {"PNG bytes under a JPEG name",
         {"render", "fence", "--size", "8x8", "-o", dir.file("x.jpg")},
         ".png"},
        {"the lit image and the visibility in one file",
         {"render", "fence", "--size", "8x8", "-o", dir.file("x.png"), "--visibility", dir.file("./x.png")},
         "same file"},
        {"stats as PNG", {"render", "fence", "--size", "8x8", "--stats", dir.file("s.png")}, ".json"},
        {"a visibility-only method's light samples",
         {"render", "fence", "--method", "pw", "--size", "8x8", "--dump-ls", dir.file("ls.npy")},
         "--visibility"},
        {"pcf's light samples",
         {"render", "fence", "--method", "pcf", "--size", "8x8", "--dump-ls", dir.file("ls.npy")},
         "--visibility"},
    };
    for (const Case& c : cases) expectOneLineError(c);
    EXPECT_FALSE(fs::exists(dir.file("x.jpg")));
    EXPECT_FALSE(fs::exists(dir.file("ls.npy")));
}

/// A version-1 .npy of 2×2×8 bytes of zeros, in Fortran or C order.
std::string npyBytes(bool fortranOrder) {
    std::string header = std::string("{'descr': '|u1', 'fortran_order': ") +
                         (fortranOrder ? "True" : "False") + ", 'shape': (2, 2, 8), }";
    header.append((64 - (10 + header.size() + 1) % 64) % 64, ' ');
    header.push_back('\n');
    std::string file("\x93NUMPY\x01\x00", 8);
    file.push_back(char(header.size() & 0xff));
    file.push_back(char(header.size() >> 8));
    return file + header + std::string(32, '\0');
}

TEST(TrustCli, AFortranOrderNpyIsRefused) {
    ScratchDir dir;
    writeText(dir.file("fortran.npy"), npyBytes(true));
    writeText(dir.file("c.npy"), npyBytes(false));
    expectOneLineError({"Fortran order", {"compare", dir.file("fortran.npy"), dir.file("c.npy")}, "Fortran"});
    // The same array in C order reads (a bitmask: an array without metadata says so with --kind).
    const CliResult ok = runStsv({"compare", dir.file("c.npy"), dir.file("c.npy"), "--kind", "bitmask"});
    EXPECT_EQ(ok.code, 0) << ok.err;
}

// Bits are compared only where both methods have them: against pcf (a v_coef per pixel) STSV's
// identical-bits column is n/a, not the 97 % that pcf's all-lit buffer used to give.
TEST(TrustCli, CompareCountsNoBitsOfAVisibilityOnlyMethod) {
    ScratchDir dir;
    const CliResult r =
        runStsv({"compare", "fence", "--methods", "stsv/cpu,dcs+stsv/cpu", "--against", "pcf/cpu", "--size",
                 "24x16", "--samples", "16", "--json", dir.file("c.json"), "--out", dir.file("out"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json j = readJson(dir.file("c.json"));
    ASSERT_TRUE(j.contains("rows")) << j.dump(1);
    for (const nlohmann::json& row : j["rows"]) EXPECT_TRUE(row["identical_percent"].is_null()) << row.dump();
    EXPECT_NE(r.out.find("n/a: every method: pcf"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(dir.file("out/stsv_cpu_bitdiff.png")));
    // And the footnote names the visibility-only methods present, not penumbra wedges always.
    const CliResult p = runStsv({"compare", "fence", "--methods", "pcss/cpu", "--against", "reference",
                                 "--size", "24x16", "--samples", "16", "-q"});
    ASSERT_EQ(p.code, 0) << p.err;
    EXPECT_NE(p.out.find("n/a: pcss give(s)"), std::string::npos) << p.out;
    EXPECT_EQ(p.out.find("penumbra wedges"), std::string::npos) << p.out;
}

// pw and dcs alone leave perforated triangles out of their shadows: they say so on stderr and
// in the stats, with the method that draws them.
TEST(TrustCli, OpaqueOnlyMethodsNameThePerforatedTrianglesTheyIgnore) {
    ScratchDir dir;
    for (const std::string method : {"pw", "dcs"}) {
        const CliResult r = runStsv({"render", "fence", "--method", method, "--backend", "cpu", "--size",
                                     "16x16", "--stats", dir.file(method + ".json"), "-q"});
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_NE(r.err.find("stsv: warning: " + method + " shades opaque triangles only"), std::string::npos)
            << r.err;
        EXPECT_NE(r.err.find(method + "+stsv draws them"), std::string::npos) << r.err;
        const nlohmann::json s = readJson(dir.file(method + ".json"));
        EXPECT_EQ(s["ignored_perforated_triangles"], 2) << s.dump(1);
        EXPECT_EQ(s["ignored_perforated_triangles_use"], method + "+stsv");
    }
    // Methods that draw them say nothing.
    const CliResult r = runStsv({"render", "fence", "--method", "dcs+stsv", "--backend", "cpu", "--size",
                                 "16x16", "--stats", dir.file("both.json"), "-q"});
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    EXPECT_FALSE(readJson(dir.file("both.json")).contains("ignored_perforated_triangles"));
}

// PCSS counts the pixels whose kernel pcss_max_kernel clamped, on both backends, and warns
// above 1 %.
TEST(TrustCli, PcssWarnsWhenItsKernelLimitShapesThePicture) {
    ScratchDir dir;
    for (const std::string backend : {"cpu", "vulkan"}) {
        const CliResult r =
            runStsv({"render", "fence", "--method", "pcss", "--backend", backend, "--size", "32x32",
                     "--param", "pcss_max_kernel=1", "--stats", dir.file(backend + ".json"), "-q"});
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_NE(r.err.find("stsv: warning: pcss clamped the filter kernel"), std::string::npos) << r.err;
        const nlohmann::json s = readJson(dir.file(backend + ".json"));
        ASSERT_TRUE(s.contains("shadow_maps")) << s.dump(1);
        EXPECT_GT(s["shadow_maps"][0]["kernel_clamped_fraction"].get<double>(), 0.01) << s.dump(1);
        const CliResult d = runStsv({"render", "fence", "--method", "pcss", "--backend", backend, "--size",
                                     "32x32", "--stats", dir.file(backend + "_default.json"), "-q"});
        ASSERT_EQ(d.code, 0) << d.err;
        EXPECT_EQ(d.err.find("warning"), std::string::npos) << d.err;
        EXPECT_EQ(readJson(dir.file(backend + "_default.json"))["shadow_maps"][0]["kernel_clamped_pixels"],
                  0);
    }
}

// The other bounds of the shadow maps' cost, counted on both backends and warned above 1 %: PCSS's
// blocker search cut to pcss_max_search, PCF's taps spread by pcf_max_radius; at the defaults the
// search is not cut on fence (the stats say 0) and nothing is said.
TEST(TrustCli, PcssSearchAndPcfTapBoundsAreCountedAndWarned) {
    ScratchDir dir;
    for (const std::string backend : {"cpu", "vulkan"}) {
        const CliResult pcss =
            runStsv({"render", "fence", "--method", "pcss", "--backend", backend, "--size", "32x32",
                     "--param", "pcss_max_search=1", "--stats", dir.file(backend + "_search.json"), "-q"});
        ASSERT_EQ(pcss.code, 0) << pcss.err;
        EXPECT_NE(pcss.err.find("stsv: warning: pcss cut the blocker search"), std::string::npos) << pcss.err;
        EXPECT_GT(readJson(dir.file(backend + "_search.json"))["shadow_maps"][0]["search_clamped_fraction"]
                      .get<double>(),
                  0.01);
        const CliResult pcssDefault =
            runStsv({"render", "fence", "--method", "pcss", "--backend", backend, "--size", "32x32",
                     "--stats", dir.file(backend + "_search_default.json"), "-q"});
        ASSERT_EQ(pcssDefault.code, 0) << pcssDefault.err;
        EXPECT_EQ(pcssDefault.err.find("warning"), std::string::npos) << pcssDefault.err;
        EXPECT_EQ(
            readJson(dir.file(backend + "_search_default.json"))["shadow_maps"][0]["search_clamped_pixels"],
            0);
        // 10 cm either side is some 30 texels on fence's ground: one tap either side spreads them
        // about 20 texels apart.
        const CliResult pcf = runStsv({"render", "fence", "--method", "pcf", "--backend", backend, "--size",
                                       "32x32", "--param", "pcf_world_radius=0.1", "--param",
                                       "pcf_max_radius=1", "--stats", dir.file(backend + "_pcf.json"), "-q"});
        ASSERT_EQ(pcf.code, 0) << pcf.err;
        EXPECT_NE(pcf.err.find("stsv: warning: pcf spread the kernel's taps"), std::string::npos) << pcf.err;
        EXPECT_GT(readJson(dir.file(backend + "_pcf.json"))["shadow_maps"][0]["kernel_strided_fraction"]
                      .get<double>(),
                  0.01);
    }
}

// A knob whose unit changed is refused with the knob that replaced it, never read in the new
// unit: pcf_radius=5 (texels) would be a 5 m kernel as pcf_world_radius.
TEST(TrustCli, KernelKnobsThatCountedTexelsAreRefusedWithTheirWorldUnitReplacement) {
    for (const auto& [method, old, replacement] : {std::tuple{"pcf", "pcf_radius=5", "pcf_world_radius"},
                                                   std::tuple{"esm", "fm_radius=2", "fm_world_radius"}}) {
        const CliResult r = runStsv({"render", "fence", "--method", method, "--backend", "cpu", "--size",
                                     "16x16", "--param", old, "-q"});
        EXPECT_EQ(r.code, 1) << r.err;
        EXPECT_NE(r.err.find(replacement), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("metres"), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
}

} // namespace
} // namespace stsv::test

namespace stsv::test {
namespace {

// Without a Vulkan driver (the loader pointed at none), the Vulkan backend says what is missing
// and how to render without it, and the CPU backend renders. ctest runs each test in its own
// process, so the environment set here reaches only this test's loader.
TEST(TrustCli, NoVulkanDriverSaysWhatToInstallAndTheCpuBackendStillRenders) {
    ScratchDir dir;
    ::setenv("VK_DRIVER_FILES", "/nonexistent/stsv_no_driver.json", 1);
    ::setenv("VK_ICD_FILENAMES", "/nonexistent/stsv_no_driver.json", 1);
    expectOneLineError({"no driver",
                        {"render", "fence", "--backend", "vulkan", "--size", "8x8", "-o", dir.file("v.png")},
                        "no Vulkan driver was found"});
    const CliResult hint =
        runStsv({"render", "fence", "--backend", "vulkan", "--size", "8x8", "-o", dir.file("v.png")});
    EXPECT_NE(hint.err.find("--backend cpu"), std::string::npos) << hint.err;
    EXPECT_NE(hint.err.find("mesa-vulkan-drivers"), std::string::npos) << hint.err;
    const CliResult cpu =
        runStsv({"render", "fence", "--backend", "cpu", "--size", "8x8", "-o", dir.file("c.png"), "-q"});
    EXPECT_EQ(cpu.code, 0) << cpu.err;
    EXPECT_TRUE(fs::exists(dir.file("c.png")));
    ::unsetenv("VK_DRIVER_FILES");
    ::unsetenv("VK_ICD_FILENAMES");
}

} // namespace
} // namespace stsv::test
