// The method table (render/methods.h): every row parses and prints, its knobs parse and reject
// bad values, and every method renders a small frame on each backend the table claims, with the
// buffer kind and stats the row says (Vulkan with validation on).
#include "gpu_render_helpers.h"

#include "core/error.h"
#include "render/methods.h"
#include "render/renderer.h"
#include "scene/load.h"

#include <gtest/gtest.h>

#include <map>

#include <set>

namespace stsv {
namespace {

TEST(MethodTable, RowsHaveUniqueIdsNamesAndBackends) {
    std::set<std::string> names;
    for (std::size_t i = 0; i < methodTable().size(); ++i) {
        const MethodInfo& m = methodTable()[i];
        EXPECT_EQ(&methodInfo(m.id), &m) << m.name; // ids are unique and name their own row
        EXPECT_TRUE(names.insert(m.name).second) << "duplicate name " << m.name;
        EXPECT_FALSE(m.backends.empty()) << m.name;
        EXPECT_FALSE(m.description.empty()) << m.name;
        EXPECT_EQ(parseMethod(m.name), m.id);
        EXPECT_EQ(toString(m.id), m.name);
        EXPECT_EQ(&findMethod(m.name), &m);
        EXPECT_TRUE(m.implementedOn(m.backends.front())) << m.name;
        // A ground-truth method traces; an object-based one composes an STSV or an opaque pass; an
        // image-based one filters a shadow map into a visibility image, and nothing else — but
        // peel, which marches every light sample's ray through its depth grid into bits.
        EXPECT_EQ(m.traced, m.family == MethodFamily::GroundTruth) << m.name;
        const bool volumes = m.stsv != StsvTriangles::None || m.wedges != WedgeVariant::None;
        EXPECT_EQ(volumes, m.family == MethodFamily::ObjectBased) << m.name;
        EXPECT_EQ(m.shadowMap != ShadowMapMethod::None, m.family == MethodFamily::ImageBased) << m.name;
        if (m.family == MethodFamily::ImageBased) {
            EXPECT_EQ(m.output, m.shadowMap == ShadowMapMethod::Peel ? MethodOutput::SampleOcclusion
                                                                     : MethodOutput::Visibility)
                << m.name;
        }
    }
    try {
        findMethod("pcf-typo");
        FAIL() << "no error for an unknown method";
    } catch (const UsageError& e) {
        for (const MethodInfo& m : methodTable())
            EXPECT_NE(std::string(e.what()).find(m.name), std::string::npos) << e.what();
    }
}

TEST(MethodTable, BufferKindFollowsWhatTheMethodWrites) {
    for (const MethodInfo& m : methodTable())
        for (BufferKind requested : {BufferKind::Bitmask, BufferKind::Counters}) {
            const BufferKind expected =
                m.output == MethodOutput::SampleCounters ? BufferKind::Counters : requested;
            EXPECT_EQ(m.bufferKind(requested), expected) << m.name;
        }
    EXPECT_EQ(methodInfo(Method::Dcs).bufferKind(BufferKind::Bitmask), BufferKind::Counters);
    EXPECT_EQ(methodInfo(Method::Stsv).bufferKind(BufferKind::Bitmask), BufferKind::Bitmask);
}

/// A row with knobs, to exercise the parameter parser (the built-in rows may have none).
MethodInfo withKnobs() {
    MethodInfo m = methodInfo(Method::Stsv);
    m.knobs = {{"size", 2048, 256, 8192, true, "texels"}, {"bias", 0.5, 0.0, 4.0, false, "texels"}};
    return m;
}

TEST(MethodTable, ParamsTakeDefaultsAndRejectUnknownNamesAndBadValues) {
    const MethodInfo m = withKnobs();
    const MethodParams defaults = parseMethodParams(m, {});
    EXPECT_EQ(defaults, (MethodParams{{"size", 2048.0}, {"bias", 0.5}}));
    const MethodParams given = parseMethodParams(m, {"size=512", "bias=1.25"});
    EXPECT_EQ(given, (MethodParams{{"size", 512.0}, {"bias", 1.25}}));

    const auto message = [&](const std::vector<std::string>& items) -> std::string {
        try {
            parseMethodParams(m, items);
        } catch (const UsageError& e) {
            return e.what();
        }
        return "";
    };
    const std::string unknown = message({"sise=512"});
    EXPECT_NE(unknown.find("sise"), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("size (256 to 8192)"), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("bias (0 to 4)"), std::string::npos) << unknown;
    EXPECT_NE(message({"size=128"}).find("out of range (256 to 8192)"), std::string::npos);
    EXPECT_NE(message({"size=300.5"}).find("not an integer"), std::string::npos);
    EXPECT_NE(message({"bias=abc"}).find("not a number"), std::string::npos);
    EXPECT_NE(message({"bias=nan"}).find("not a number"), std::string::npos);
    EXPECT_NE(message({"bias"}).find("name=value"), std::string::npos);
    EXPECT_NE(message({"bias="}).find("not a number"), std::string::npos);
    // The built-in rows: a knob none of them has is rejected with the row's (empty) list.
    for (const MethodInfo& row : methodTable()) {
        EXPECT_THROW(parseMethodParams(row, {"no_such_knob=1"}), UsageError) << row.name;
        EXPECT_EQ(parseMethodParams(row, {}).size(), row.knobs.size()) << row.name;
    }
    RenderOptions o;
    o.params = {{"no_such_knob", 1.0}};
    EXPECT_THROW(validate(o), UsageError);
}

class MethodTableRender : public test::GpuRenderTest {};

TEST_F(MethodTableRender, EveryMethodRendersOnEveryBackendItClaims) {
    const Scene scene = loadScene("fence");
    for (const MethodInfo& m : methodTable())
        for (Backend backend : m.backends) {
            const std::string label = m.name + "/" + toString(backend);
            RenderOptions o = test::gpuOptions(32, 32, 16);
            o.method = m.id;
            o.backend = backend;
            o.params = parseMethodParams(m, {});
            const Frame frame =
                backend == Backend::Vulkan ? renderGpu(scene, o) : makeRenderer(scene, o)->render();
            ASSERT_EQ(frame.lightSamples.size(), scene.lights.size()) << label;
            EXPECT_EQ(frame.lightSamples[0].kind(), m.bufferKind(o.buffer)) << label;
            EXPECT_EQ(frame.lightSamples[0].width(), 32) << label;
            EXPECT_EQ(frame.visibility.width, 32) << label;
            EXPECT_EQ(frame.stats["options"]["method"].get<std::string>(), m.name) << label;
            EXPECT_EQ(frame.stats["options"]["backend"].get<std::string>(), toString(backend)) << label;
            EXPECT_EQ(frame.stats["options"]["params"].size(), m.knobs.size()) << label;
            // The fence casts its shadow for every method that treats perforated triangles, but
            // peel: its open quad is a lone back face, which the closed-object rule lets light
            // through (Peel.TheOpenFenceLetsLightThroughItsLoneBackFaces).
            float darkest = 1.0f;
            for (float v : frame.visibility.pixels) {
                EXPECT_TRUE(v >= 0.0f && v <= 1.0f + 1e-6f) << label << " v=" << v;
                darkest = std::min(darkest, v);
            }
            const bool shadows =
                m.traced || m.stsv != StsvTriangles::None ||
                (m.shadowMap != ShadowMapMethod::None && m.shadowMap != ShadowMapMethod::Peel);
            if (shadows) {
                EXPECT_LT(darkest, 0.9f) << label;
            }
        }
}

TEST_F(MethodTableRender, StatsNameTheSameFamiliesOnBothBackends) {
    // The families a frame reports are those its method runs, on either backend: "stsv" where
    // STSV runs, "wedges" where an opaque technique does, "shadow_maps" for image-based methods
    // (with the same keys). Within "wedges", "center" only from Vulkan, whose centre pass walks
    // the tree and counts its visits (the CPU mirror walks it without counting).
    const Scene scene = loadScene("fence");
    for (const MethodInfo& m : methodTable()) {
        if (!m.implementedOn(Backend::Cpu) || !m.implementedOn(Backend::Vulkan)) continue;
        std::map<Backend, nlohmann::json> stats;
        for (Backend backend : {Backend::Cpu, Backend::Vulkan}) {
            RenderOptions o = test::gpuOptions(16, 12, 16);
            o.method = m.id;
            o.backend = backend;
            o.params = parseMethodParams(m, {});
            stats[backend] =
                (backend == Backend::Vulkan ? renderGpu(scene, o) : makeRenderer(scene, o)->render()).stats;
        }
        const bool opaque = m.wedges != WedgeVariant::None;
        for (Backend backend : {Backend::Cpu, Backend::Vulkan}) {
            const nlohmann::json& j = stats[backend];
            const std::string label = m.name + "/" + toString(backend);
            EXPECT_EQ(j.contains("stsv"), m.stsv != StsvTriangles::None) << label;
            EXPECT_EQ(j.contains("wedges"), opaque) << label;
            EXPECT_EQ(j.contains("shadow_maps"), m.shadowMap != ShadowMapMethod::None) << label;
            EXPECT_FALSE(j.contains("center")) << label;
            if (opaque) {
                EXPECT_EQ(j["wedges"][0].contains("center"), backend == Backend::Vulkan) << label;
            }
        }
        if (m.shadowMap != ShadowMapMethod::None) {
            const nlohmann::json& cpu = stats[Backend::Cpu]["shadow_maps"][0];
            const nlohmann::json& gpu = stats[Backend::Vulkan]["shadow_maps"][0];
            EXPECT_EQ(cpu.size(), gpu.size()) << m.name << ": " << cpu.dump() << " vs " << gpu.dump();
            for (const auto& [key, value] : cpu.items())
                EXPECT_TRUE(gpu.contains(key)) << m.name << ": " << key;
            EXPECT_EQ(cpu["faces"], gpu["faces"]) << m.name;
            EXPECT_EQ(cpu["texels"], gpu["texels"]) << m.name;
        }
    }
}

TEST(MethodTable, MakeRendererRefusesABackendTheRowLacks) {
    const Scene scene = loadScene("fence");
    for (const MethodInfo& m : methodTable())
        for (Backend backend : {Backend::Cpu, Backend::Vulkan}) {
            if (m.implementedOn(backend)) continue;
            RenderOptions o = test::gpuOptions(8, 8, 16);
            o.method = m.id;
            o.backend = backend;
            EXPECT_THROW(makeRenderer(scene, o), UsageError) << m.name << "/" << toString(backend);
        }
}

} // namespace
} // namespace stsv
