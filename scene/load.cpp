#include "scene/load.h"

#include "core/error.h"
#include "core/files.h"
#include "scene/geometry.h"
#include "scene/gltf_scene.h"
#include "scene/json_scene.h"
#include "scene/mesh_fence.h"
#include "scene/mesh_io.h"
#include "scene/procedural.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <ostream>

namespace stsv {

namespace {

struct Builtin {
    const char* name;
    const char* description;
    std::vector<SceneKnob> knobs;
};

std::string rangeText(const SceneKnob& knob) {
    return stsv::rangeText(ParamRange{knob.lo, knob.hi});
}

/// A knob whose description ends with its range, declared once from the scene's ParamRange.
SceneKnob knob(const char* name, const char* defaultValue, const std::string& text, SceneKnob::Kind kind,
               const ParamRange& range) {
    SceneKnob k{name, defaultValue, text, kind, range.lo, range.hi};
    k.description += ", " + rangeText(k);
    return k;
}
SceneKnob real(const char* name, const char* defaultValue, const std::string& text, const ParamRange& range) {
    return knob(name, defaultValue, text, SceneKnob::Kind::Real, range);
}
SceneKnob integer(const char* name, const char* defaultValue, const std::string& text,
                  const ParamRange& range) {
    return knob(name, defaultValue, text, SceneKnob::Kind::Integer, range);
}
SceneKnob seed(const char* name, const std::string& text) {
    return {name, "1", text + ", unsigned 64-bit integer", SceneKnob::Kind::Seed, 0.0, 0.0};
}

/// The knobs' ranges are the scenes' own (procedural.h, mesh_fence.h; the knot's here).
constexpr ParamRange KNOT_SEGMENTS{3, 20000};
constexpr ParamRange KNOT_SIDES{3, 200};

const std::vector<Builtin>& builtins() {
    static const std::vector<Builtin> list = {
        {"fence",
         "a 4 m x 2 m chain-link fence (2 perforated triangles) on a ground plane under a square light",
         {real("light_size", "1", "edge of the square light, metres", FENCE_LIGHT_SIZE),
          integer("repeat", "16",
                  "chain-link tiles across the fence width (height gets repeat/2; repeat x texture_size "
                  "below 2^24)",
                  FENCE_REPEAT),
          integer("texture_size", "256", "texels per edge of the chain-link texture", GENERATED_TEXTURE_SIZE),
          real("fabric", "0", "opacity of a translucent fabric hung 0.3 m behind the fence; 0 = none",
               FENCE_FABRIC)}},
        {"foliage",
         "a square patch of plants (2 crossed leaf quads = 4 perforated triangles each) on a ground plane",
         {integer("count", "64", "number of plants (S-triangles = 4 x count)", FOLIAGE_COUNT),
          seed("seed", "seed of placement, size and orientation"),
          real("spacing", "0.75", "metres between neighbouring plants (the patch grows with count)",
               FOLIAGE_SPACING),
          real("light_size", "0",
               "edge of the square light, metres; 0 = a quarter of the patch edge (a large light moves "
               "back to clear the plants)",
               FOLIAGE_LIGHT_SIZE),
          integer("texture_size", "128", "texels per edge of the leaf texture", GENERATED_TEXTURE_SIZE)}},
        {"fence-mesh",
         "the fence scene with its chain-link quad turned into a closed opaque mesh (one box per run of "
         "opaque texels)",
         {real("light_size", "1", "edge of the square light, metres", FENCE_MESH_LIGHT_SIZE),
          integer("repeat", "16",
                  "chain-link tiles across the fence width (height gets repeat/2; triangles grow as "
                  "repeat^2)",
                  FENCE_MESH_REPEAT),
          integer("texture_size", "256", "texels per edge of the chain-link texture (triangles grow with it)",
                  FENCE_MESH_TEXTURE_SIZE),
          real("thickness", "0.0005", "depth of the wire boxes, metres", TEXEL_BOX_THICKNESS)}},
        {"particles",
         "light-facing translucent billboards of Gaussian alpha in a ball beside an opaque cube (Klein et "
         "al.'s "
         "particle scene; --buffer transmittance)",
         {integer("count", "1000", "billboards (2 translucent triangles each)", PARTICLES_COUNT),
          real("opacity", "0.5", "peak alpha at a particle's centre", PARTICLES_OPACITY),
          real("height", "2",
               "height of the cloud's centre, metres (below 1.45 the cloud rests on the ground, whose "
               "receivers then lie inside it)",
               PARTICLES_HEIGHT),
          seed("seed", "seed of placement")}},
        {"knot",
         "a closed (2, 3) torus-knot mesh on a ground plane under a square light (opaque occluders: dcs, "
         "pw)",
         {integer("segments", "480", "tube segments along the knot", KNOT_SEGMENTS),
          integer("sides", "12", "tube sides around the knot (triangles = 2 x segments x sides)",
                  KNOT_SIDES)}},
    };
    return list;
}

const Builtin* findBuiltin(const std::string& name) {
    for (const Builtin& b : builtins())
        if (name == b.name) return &b;
    return nullptr;
}

std::string joinNames(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out.empty() ? "none" : out;
}

/// Knob values of one scene: unknown keys rejected up front, typed getters with ranges.
class Knobs {
  public:
    Knobs(const std::string& scene, const SceneOptions& options, const std::vector<SceneKnob>& accepted)
        : m_scene(scene), m_options(options), m_accepted(accepted) {
        std::vector<std::string> names;
        names.reserve(accepted.size());
        for (const SceneKnob& k : accepted) names.push_back(k.name);
        for (const auto& [key, value] : options.set)
            if (std::find(names.begin(), names.end(), key) == names.end()) {
                std::string message = "scene '" + scene + "' has no knob '";
                message += key;
                message += "' (accepted: ";
                message += joinNames(names);
                message += ")";
                throw UsageError(message);
            }
    }

    /// An Integer knob's value, or `fallback` when not set.
    long long integer(const std::string& name, long long fallback) const {
        const auto it = m_options.set.find(name);
        if (it == m_options.set.end()) return fallback;
        const SceneKnob& k = declared(name);
        long long value = 0;
        const std::string& text = it->second;
        const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (ec != std::errc() || ptr != text.data() + text.size() || double(value) < k.lo ||
            double(value) > k.hi)
            throw UsageError("scene '" + m_scene + "': knob " + name + "=" + text +
                             " must be an integer in " + rangeText(k));
        return value;
    }

    /// A Seed knob's value, or `fallback` when not set.
    std::uint64_t unsigned64(const std::string& name, std::uint64_t fallback) const {
        const auto it = m_options.set.find(name);
        if (it == m_options.set.end()) return fallback;
        std::uint64_t value = 0;
        const std::string& text = it->second;
        const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (ec != std::errc() || ptr != text.data() + text.size())
            throw UsageError("scene '" + m_scene + "': knob " + name + "=" + text +
                             " must be an unsigned integer");
        return value;
    }

    /// A Real knob's value, or `fallback` when not set.
    float real(const std::string& name, float fallback) const {
        const auto it = m_options.set.find(name);
        if (it == m_options.set.end()) return fallback;
        const SceneKnob& k = declared(name);
        double value = 0.0;
        const std::string& text = it->second;
        const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
        if (ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(value) || value < k.lo ||
            value > k.hi)
            throw UsageError("scene '" + m_scene + "': knob " + name + "=" + text + " must be a number in " +
                             rangeText(k));
        return float(value);
    }

  private:
    const SceneKnob& declared(const std::string& name) const {
        for (const SceneKnob& k : m_accepted)
            if (k.name == name) return k;
        throw Error("internal: scene '" + m_scene + "' reads an undeclared knob '" + name + "'");
    }

    std::string m_scene;
    const SceneOptions& m_options;
    const std::vector<SceneKnob>& m_accepted;
};

} // namespace

std::ostream& operator<<(std::ostream& out, const SceneKnob& knob) {
    return out << knob.name << '=' << knob.defaultValue;
}

std::vector<std::string> builtinSceneNames() {
    std::vector<std::string> names;
    for (const Builtin& b : builtins()) names.emplace_back(b.name);
    return names;
}

std::vector<SceneKnob> builtinSceneKnobs(const std::string& name) {
    const Builtin* b = findBuiltin(name);
    if (!b)
        throw UsageError("unknown built-in scene '" + name +
                         "' (built-ins: " + joinNames(builtinSceneNames()) + ")");
    return b->knobs;
}

std::string describeBuiltinScene(const std::string& name) {
    const Builtin* b = findBuiltin(name);
    if (!b)
        throw UsageError("unknown built-in scene '" + name +
                         "' (built-ins: " + joinNames(builtinSceneNames()) + ")");
    return b->description;
}

namespace {

Scene loadWithoutOverrides(const std::string& spec, const SceneOptions& options);

} // namespace

Scene loadScene(const std::string& spec, const SceneOptions& options) {
    Scene scene = loadWithoutOverrides(spec, options);
    if (!options.camera.empty()) scene.camera = parseCameraJson("--camera", options.camera);
    if (!options.lights.empty()) scene.lights.clear();
    for (const std::string& light : options.lights) scene.lights.push_back(parseLightJson("--light", light));
    for (const std::string& light : options.addLights)
        scene.lights.push_back(parseLightJson("--add-light", light));
    if (!options.camera.empty() || !options.lights.empty() || !options.addLights.empty()) scene.validate();
    return scene;
}

namespace {

Scene loadWithoutOverrides(const std::string& spec, const SceneOptions& options) {
    if (const Builtin* b = findBuiltin(spec)) {
        const Knobs knobs(spec, options, b->knobs);
        if (spec == "fence") {
            FenceParams p;
            p.lightSize = knobs.real("light_size", p.lightSize);
            p.repeat = int(knobs.integer("repeat", p.repeat));
            p.textureSize = int(knobs.integer("texture_size", p.textureSize));
            p.fabric = knobs.real("fabric", p.fabric);
            return makeFenceScene(p);
        }
        if (spec == "fence-mesh") {
            FenceParams p;
            p.lightSize = knobs.real("light_size", p.lightSize);
            p.repeat = int(knobs.integer("repeat", p.repeat));
            p.textureSize = int(knobs.integer("texture_size", p.textureSize));
            TexelBoxOptions boxes;
            boxes.thickness = knobs.real("thickness", boxes.thickness);
            return makeFenceMeshScene(p, boxes);
        }
        if (spec == "particles") {
            ParticlesParams p;
            p.count = int(knobs.integer("count", p.count));
            p.opacity = knobs.real("opacity", p.opacity);
            p.height = knobs.real("height", p.height);
            p.seed = knobs.unsigned64("seed", p.seed);
            checkSceneMemory("scene 'particles' (count=" + std::to_string(p.count) + ")",
                             2.0 * p.count + 14.0);
            return makeParticlesScene(p);
        }
        if (spec == "knot") {
            const int segments = int(knobs.integer("segments", 480));
            const int sides = int(knobs.integer("sides", 12));
            checkSceneMemory("scene 'knot' (segments=" + std::to_string(segments) +
                                 ", sides=" + std::to_string(sides) + ")",
                             2.0 * segments * sides);
            return makeMeshScene(makeTorusKnotMesh(segments, sides, 0.12f), "knot");
        }
        FoliageParams p;
        p.count = int(knobs.integer("count", p.count));
        p.seed = knobs.unsigned64("seed", p.seed);
        p.spacing = knobs.real("spacing", p.spacing);
        p.lightSize = knobs.real("light_size", p.lightSize);
        p.textureSize = int(knobs.integer("texture_size", p.textureSize));
        checkSceneMemory("scene 'foliage' (count=" + std::to_string(p.count) + ")", 4.0 * p.count + 2.0);
        return makeFoliageScene(p);
    }
    const std::string ext = lowerExtension(spec);
    if (ext.empty())
        throw UsageError("unknown scene '" + spec + "': expected a built-in name (" +
                         joinNames(builtinSceneNames()) + ") or a .json, .obj, .off, .gltf or .glb file");
    if (ext != ".json" && ext != ".obj" && ext != ".off" && ext != ".gltf" && ext != ".glb")
        throw UsageError("scene file '" + spec + "' has an unsupported extension '" + ext +
                         "' (expected .json, .obj, .off, .gltf or .glb)");
    const Knobs knobs(spec, options, {}); // files take no knobs
    Scene scene;
    if (ext == ".json") {
        scene = loadJsonScene(spec);
    } else if (ext == ".gltf" || ext == ".glb") {
        // On the ground under the default light, as a bare mesh; the file's camera if it has one.
        std::optional<Camera> camera;
        scene = makeMeshScene(loadGltf(spec, &camera), spec);
        if (camera) scene.camera = *camera;
        scene.validate();
    } else {
        scene = makeMeshScene(loadMeshFile(spec), spec);
    }
    checkSceneMemory(spec, double(scene.triangles.size()));
    return scene;
}

} // namespace

} // namespace stsv
