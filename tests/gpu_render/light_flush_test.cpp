// A light in the plane of a surface: flush with its ceiling, on the underside of a shelf (coplanar
// with one of a box's faces), at the top of a recess in the ceiling. Every light sample then lies
// on a surface, and whether the segment p → s ending there counts that surface as a hit was left
// to round-off: the reference left the room dark while STSV lit it. The rule (shadowTMax,
// scene/occlusion_rules_dh.h) stops every segment short of its sample by the gap it starts with,
// so the surface the sample lies on never occludes it. Each room is checked against a hand-worked
// answer, computed here in double from the room's dimensions: every method with per-sample output
// sample by sample, on both backends; every method that writes a visibility per pixel on average.
#include "gpu_render_helpers.h"

#include <glm/gtx/string_cast.hpp>

#include <array>

namespace stsv::test {
namespace {

constexpr float ROOM_HALF = 2.0f;    ///< the room spans [−2, 2] in x and z
constexpr float CEILING = 2.5f;      ///< y of the ceiling
constexpr float LIGHT_HALF = 0.3f;   ///< half the edge of the square light
constexpr float HOLE_HALF = 0.5f;    ///< the recess: a hole of [−0.5, 0.5]² in the ceiling …
constexpr float RECESS_DEPTH = 0.3f; ///< … under a box 0.3 high, the light flush with its top
constexpr float SHELF_BOTTOM = 1.6f; ///< the shelf: [−0.5, 0.5]² × [1.6, 1.8], the light under it
constexpr float SHELF_TOP = 1.8f;

enum class Room { Flush, Shelf, Recess };

const char* roomName(Room room) {
    return room == Room::Flush ? "flush ceiling" : room == Room::Shelf ? "shelf underside" : "recess";
}

/// The quad a, b, c, d (counter-clockwise seen from the side it faces).
void addQuad(Scene& s, vec3 a, vec3 b, vec3 c, vec3 d) {
    s.addTriangle(a, b, c, vec2(0, 0), vec2(1, 0), vec2(1, 1), 0);
    s.addTriangle(a, c, d, vec2(0, 0), vec2(1, 1), vec2(0, 1), 0);
}

/// Horizontal quad at height y over [x0, x1] × [z0, z1], facing down when `down`.
void addHorizontal(Scene& s, float y, float x0, float x1, float z0, float z1, bool down) {
    const vec3 a(x0, y, z0), b(x1, y, z0), c(x1, y, z1), d(x0, y, z1);
    if (down)
        addQuad(s, a, b, c, d);
    else
        addQuad(s, a, d, c, b);
}

/// The four vertical sides of the box [x0, x1] × [y0, y1] × [z0, z1].
void addSides(Scene& s, float x0, float x1, float y0, float y1, float z0, float z1) {
    addQuad(s, vec3(x0, y0, z0), vec3(x1, y0, z0), vec3(x1, y1, z0), vec3(x0, y1, z0));
    addQuad(s, vec3(x1, y0, z1), vec3(x0, y0, z1), vec3(x0, y1, z1), vec3(x1, y1, z1));
    addQuad(s, vec3(x0, y0, z1), vec3(x0, y0, z0), vec3(x0, y1, z0), vec3(x0, y1, z1));
    addQuad(s, vec3(x1, y0, z0), vec3(x1, y0, z1), vec3(x1, y1, z1), vec3(x1, y1, z0));
}

Scene makeRoom(Room room) {
    Scene s;
    s.source = roomName(room);
    s.materials.push_back({"wall", vec3(0.7f), -1, WrapMode::Repeat, true});
    const float h = ROOM_HALF;
    addHorizontal(s, 0.0f, -h, h, -h, h, false);
    addSides(s, -h, h, 0.0f, CEILING, -h, h);
    float lightY = CEILING;
    if (room == Room::Recess) {
        // The ceiling around the hole, the recess's sides and its top.
        const float k = HOLE_HALF;
        addHorizontal(s, CEILING, -h, -k, -h, h, true);
        addHorizontal(s, CEILING, k, h, -h, h, true);
        addHorizontal(s, CEILING, -k, k, -h, -k, true);
        addHorizontal(s, CEILING, -k, k, k, h, true);
        addSides(s, -k, k, CEILING, CEILING + RECESS_DEPTH, -k, k);
        addHorizontal(s, CEILING + RECESS_DEPTH, -k, k, -k, k, true);
        lightY = CEILING + RECESS_DEPTH;
    } else {
        addHorizontal(s, CEILING, -h, h, -h, h, true);
    }
    if (room == Room::Shelf) {
        addSides(s, -0.5f, 0.5f, SHELF_BOTTOM, SHELF_TOP, -0.5f, 0.5f);
        addHorizontal(s, SHELF_BOTTOM, -0.5f, 0.5f, -0.5f, 0.5f, true);
        addHorizontal(s, SHELF_TOP, -0.5f, 0.5f, -0.5f, 0.5f, false);
        lightY = SHELF_BOTTOM;
    }
    s.lights.push_back(makeRectangleLight(vec3(0.0f, lightY, 0.0f), vec3(0.0f, -1.0f, 0.0f),
                                          vec2(2.0f * LIGHT_HALF), vec3(10.0f), vec3(1.0f, 0.0f, 0.0f)));
    // From a corner, below the shelf, seeing the floor, three walls and the ceiling.
    s.camera.eye = vec3(1.8f, 1.4f, 1.8f);
    s.camera.target = vec3(-0.6f, 0.6f, -0.8f);
    s.camera.up = vec3(0.0f, 1.0f, 0.0f);
    s.camera.fovY = 75.0f;
    s.validate();
    return s;
}

/// The hand-worked answer for receiver p and light sample s of `room`: +1 visible, 0 occluded, −1
/// no answer (p is not below every surface the rule is about, or the segment passes within 1e-3
/// of an edge, where float round-off may decide).
int expectedVisible(Room room, dvec3 p, dvec3 s) {
    constexpr double tie = 1e-3;
    if (room == Room::Shelf) {
        // Below the shelf every segment to its underside stays in the room and below the shelf.
        return p.y < SHELF_BOTTOM - tie ? 1 : -1;
    }
    if (p.y > CEILING - tie) return -1; // the ceiling itself, the recess
    if (room == Room::Flush) return 1;  // the room is convex: nothing lies between p and s
    // Recess: the segment leaves the room through the plane of the ceiling at t = (H − p.y)/(s.y − p.y);
    // inside the hole it reaches the light (the recess's sides lie outside the segment's span,
    // which stays within the hole's column: both ends do), elsewhere the ceiling blocks it.
    const double t = (double(CEILING) - p.y) / (s.y - p.y);
    const dvec3 q = p + t * (s - p);
    const double inside = HOLE_HALF - std::max(std::abs(q.x), std::abs(q.z));
    if (std::abs(inside) < tie) return -1;
    return inside > 0.0 ? 1 : 0;
}

struct Agreement {
    std::size_t checked = 0;    ///< samples with an answer
    std::size_t wrong = 0;      ///< of those, on the other side
    double expectedVisible = 0; ///< Σ over answered pixels of their answered visible fraction
    double methodVisible = 0;   ///< Σ over the same pixels of the method's visibility
    std::size_t pixels = 0;
    std::size_t litPixels = 0;     ///< answered pixels that see every sample, 0.1 m below the light
    std::size_t darkLitPixels = 0; ///< of those, where the method's visibility is below one half
    double litVisibility = 0;      ///< Σ of the method's visibility over those
    std::string firstWrong;
};

Agreement check(Room room, const Scene& scene, const RenderOptions& options, const Frame& frame,
                bool perSample) {
    const SamplePlan plan = samplePlanOf(options);
    const float far = farDistanceFor(scene.bounds());
    const GBuffer& g = frame.gbuffer;
    Agreement a;
    std::array<vec2, 256> points{};
    for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x) {
            const std::size_t i = g.index(x, y);
            if (!g.covered(i)) continue;
            const vec3 p = g.position[i];
            const LightFrame lf = lightFrame(scene.lights[0], p, far);
            pixelSamplePoints(plan, x, y, lf.domain, points.data());
            std::size_t answered = 0, visible = 0;
            for (int k = 0; k < plan.count; ++k) {
                const vec3 s = lightSamplePosition(lf, points[std::size_t(k)]);
                const int expected = expectedVisible(room, dvec3(p), dvec3(s));
                if (expected < 0) continue;
                ++answered;
                visible += std::size_t(expected);
                if (!perSample) continue;
                ++a.checked;
                const bool got = frame.lightSamples[0].visible(x, y, k);
                if (got != (expected == 1) && a.wrong++ == 0) {
                    std::ostringstream m;
                    m << "pixel (" << x << "," << y << ") sample " << k << " p=" << glm::to_string(p)
                      << " s=" << glm::to_string(s) << ": expected " << (expected ? "visible" : "occluded");
                    a.firstWrong = m.str();
                }
            }
            if (answered != std::size_t(plan.count)) continue;
            ++a.pixels;
            a.expectedVisible += double(visible) / double(answered);
            const float v = frame.visibility.at(x, y, 0);
            a.methodVisible += v;
            // Lit, for the approximate methods: the whole light in view, from 0.1 m or more below
            // its plane (a map from the light centre stretches its texels toward that plane's
            // horizon, where every map method has a band of errors of its own).
            if (visible == answered && p.y < scene.lights[0].position.y - 0.1f) {
                ++a.litPixels;
                a.litVisibility += v;
                a.darkLitPixels += v < 0.5f;
            }
        }
    return a;
}

/// Renders `scene` with every method on every backend it lists. The exact methods (per-sample
/// output of the object-based families and the reference) must give the hand-worked answer sample by
/// sample; the approximate ones (peel's depth grid, the per-pixel maps, PW's wedges) carry errors
/// of their own (a penumbra through the recess's rim), so they must light what sees the whole light.
class LightFlushTest : public GpuRenderTest {
  protected:
    Frame render(const Scene& scene, const MethodInfo& row, Backend backend) {
        RenderOptions options = optionsFor(row, backend);
        return backend == Backend::Vulkan ? renderGpu(scene, options)
                                          : makeCpuRenderer(scene, options)->render();
    }
    static RenderOptions optionsFor(const MethodInfo& row, Backend backend) {
        RenderOptions options;
        options.method = row.id;
        options.backend = backend;
        options.width = 56;
        options.height = 42;
        options.samples = 32;
        options.seed = 3;
        // Maps of 512² (the default's cube of CSM's 16 terms exceeds what lavapipe allocates).
        if (row.knob("sm_size")) options.params["sm_size"] = 512;
        return options;
    }
    void checkEveryMethod(Room room) {
        const Scene scene = makeRoom(room);
        for (const MethodInfo& row : methodTable()) {
            const bool exact =
                row.output != MethodOutput::Visibility && row.shadowMap == ShadowMapMethod::None;
            for (Backend backend : row.backends) {
                SCOPED_TRACE(std::string(roomName(room)) + ", " + row.name + "/" + toString(backend));
                const Frame frame = render(scene, row, backend);
                const Agreement a = check(room, scene, optionsFor(row, backend), frame, exact);
                ASSERT_GT(a.pixels, 1000u) << "the camera sees the room";
                if (exact) {
                    // Exact: the answer's ties are excluded, and every other sample lies 1e-3 or
                    // more from an edge, far beyond float round-off at these 2.5 m distances.
                    EXPECT_GT(a.checked, 30000u);
                    EXPECT_EQ(a.wrong, 0u) << a.firstWrong;
                    EXPECT_NEAR(a.methodVisible, a.expectedVisible, 1e-3 * double(a.pixels));
                    continue;
                }
                // Approximate: where the whole light is in view the room is lit, not dark, in at
                // least 99 % of those pixels, and on average within 0.05 of fully lit (the maps'
                // biases and filters darken some of it: measured at worst 0.968, MSM and PCSS under the
                // shelf).
                EXPECT_GT(a.litPixels, 300u);
                std::cout << roomName(room) << " " << row.name << "/" << toString(backend) << ": lit pixels "
                          << a.litPixels << ", dark " << a.darkLitPixels << ", mean "
                          << a.litVisibility / double(a.litPixels) << "\n";
                EXPECT_LE(double(a.darkLitPixels), 0.01 * double(a.litPixels))
                    << "pixels dark where all is lit";
                EXPECT_GT(a.litVisibility / double(a.litPixels), 0.95);
            }
        }
    }
};

TEST_F(LightFlushTest, ARoomWhoseLightIsFlushWithTheCeilingIsLit) {
    checkEveryMethod(Room::Flush);
}

TEST_F(LightFlushTest, ALightOnAShelfsUndersideLightsTheRoomBelow) {
    checkEveryMethod(Room::Shelf);
}

TEST_F(LightFlushTest, ALightAtTheTopOfARecessLightsWhatSeesItThroughTheHole) {
    checkEveryMethod(Room::Recess);
}

} // namespace
} // namespace stsv::test
