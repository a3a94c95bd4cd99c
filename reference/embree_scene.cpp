#include "reference/embree_scene.h"

#include "core/error.h"
#include "core/parallel.h"
#include "scene/occlusion_rules_dh.h"

#include <algorithm>
#include <cstdlib>
#include <string>

namespace stsv {

namespace {

/// Intersection context carrying what the filter needs (Embree 3 idiom: the context struct
/// is the first member, so the filter can cast back).
struct FilterContext {
    RTCIntersectContext rtc;
    const Scene* scene;
    std::uint32_t ignoreTriangle;
    std::vector<std::uint32_t>* collect; ///< when set: record every blocking triangle and go on
    std::vector<Hit>* hits;              ///< when set: record every hit (t, triangle, bary) and go on
    bool skipTranslucent;                ///< primary rays: Blend triangles are not receivers
    /// When set: a translucent triangle's crossing records (triangle, optical-depth units) and
    /// goes on, or blocks where its texel has α = 1; depthTables holds each material's table.
    std::vector<std::pair<std::uint32_t, std::uint32_t>>* crossings;
    const std::vector<OpticalDepthTable>* depthTables;
    /// When set: every hit records (t, triangle, units) of its texel and goes on.
    std::vector<SurfaceCrossing>* surfaces;
};

vec2 hitTexcoord(const Scene& scene, std::uint32_t tri, vec2 bary) {
    const uvec3 idx = scene.triangles[tri];
    return scene.texcoords[idx.x] + bary.x * (scene.texcoords[idx.y] - scene.texcoords[idx.x]) +
           bary.y * (scene.texcoords[idx.z] - scene.texcoords[idx.x]);
}

/// The alpha byte of `texture` at uv under the shared texel rule.
std::uint8_t texelAlpha(const Texture& texture, const Material& material, vec2 uv) {
    const ivec2 texel = texelAt(uv, ivec2(texture.width, texture.height),
                                material.wrap == WrapMode::Clamp ? WRAP_CLAMP : WRAP_REPEAT);
    return texture.alpha(texel.x, texel.y);
}

/// The optical-depth units a translucent triangle's texel at the hit adds (its material's table at
/// the blend texture's alpha byte, or at 255 without one).
std::uint32_t translucentUnits(const FilterContext& ctx, std::uint32_t tri, vec2 bary) {
    const Scene& scene = *ctx.scene;
    const Material& material = scene.materialOf(tri);
    const std::uint8_t alpha = material.blendTexture < 0
                                   ? 255
                                   : texelAlpha(scene.textures[std::size_t(material.blendTexture)], material,
                                                hitTexcoord(scene, tri, bary));
    return (*ctx.depthTables)[scene.triangleMaterial[tri]][alpha];
}

/// The units any triangle's texel at the hit takes: a translucent one's (translucentUnits),
/// OPTICAL_DEPTH_OPAQUE where an opaque or perforated one blocks, else 0.
std::uint32_t hitUnits(const FilterContext& ctx, std::uint32_t tri, vec2 bary) {
    const Scene& scene = *ctx.scene;
    const Material& material = scene.materialOf(tri);
    if (material.translucent()) return translucentUnits(ctx, tri, bary);
    if (!material.perforated()) return OPTICAL_DEPTH_OPAQUE;
    const Texture& texture = scene.textures[static_cast<std::size_t>(material.alphaTexture)];
    return alphaBlocks(texelAlpha(texture, material, hitTexcoord(scene, tri, bary))) ? OPTICAL_DEPTH_OPAQUE
                                                                                     : 0u;
}

/// The texel rule at the hit: transparent texels and the ignored triangle reject the hit.
void alphaFilter(const RTCFilterFunctionNArguments* args) {
    const auto* ctx = reinterpret_cast<const FilterContext*>(args->context);
    const Scene& scene = *ctx->scene;
    for (unsigned i = 0; i < args->N; ++i) {
        if (args->valid[i] != -1) continue;
        const std::uint32_t tri = RTCHitN_primID(args->hit, args->N, i);
        if (tri == ctx->ignoreTriangle) {
            args->valid[i] = 0;
            continue;
        }
        const Material& material = scene.materialOf(tri);
        if (material.translucent() && ctx->skipTranslucent) {
            args->valid[i] = 0;
            continue;
        }
        const vec2 bary(RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i));
        if (ctx->surfaces) {
            const std::uint32_t units = hitUnits(*ctx, tri, bary);
            if (units != 0u) ctx->surfaces->push_back({RTCRayN_tfar(args->ray, args->N, i), tri, units});
            args->valid[i] = 0;
            continue;
        }
        if (material.translucent() && ctx->crossings) {
            const std::uint32_t units = translucentUnits(*ctx, tri, bary);
            if (units == OPTICAL_DEPTH_OPAQUE) continue; // blocks: the query stops here
            if (units != 0u) ctx->crossings->push_back({tri, units});
            args->valid[i] = 0;
            continue;
        }
        if (!material.perforated()) continue;
        const Texture& texture = scene.textures[static_cast<std::size_t>(material.alphaTexture)];
        if (!alphaBlocks(texelAlpha(texture, material, hitTexcoord(scene, tri, bary)))) args->valid[i] = 0;
    }
    if (ctx->hits) {
        for (unsigned i = 0; i < args->N; ++i) {
            if (args->valid[i] != -1) continue;
            ctx->hits->push_back({RTCRayN_tfar(args->ray, args->N, i), RTCHitN_primID(args->hit, args->N, i),
                                  vec2(RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i))});
            args->valid[i] = 0;
        }
    }
    if (ctx->collect) {
        for (unsigned i = 0; i < args->N; ++i) {
            if (args->valid[i] != -1) continue;
            ctx->collect->push_back(RTCHitN_primID(args->hit, args->N, i));
            args->valid[i] = 0;
        }
    }
}

/// The ray o + t·d, t in [tNear, tFar], with no hit yet.
RTCRayHit rayHit(vec3 o, vec3 d, float tNear, float tFar) {
    RTCRayHit rh{};
    rh.ray.org_x = o.x;
    rh.ray.org_y = o.y;
    rh.ray.org_z = o.z;
    rh.ray.dir_x = d.x;
    rh.ray.dir_y = d.y;
    rh.ray.dir_z = d.z;
    rh.ray.tnear = tNear;
    rh.ray.tfar = tFar;
    rh.ray.mask = 0xffffffffu;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    return rh;
}

void checkDevice(RTCDevice device, const char* what) {
    const RTCError code = rtcGetDeviceError(device);
    if (code != RTC_ERROR_NONE)
        throw Error(std::string("Embree: ") + what + " failed (error " + std::to_string(int(code)) + ")");
}

} // namespace

EmbreeScene::EmbreeScene(const Scene& scene) : m_scene(scene) {
    for (const Material& m : scene.materials) m_depthTables.push_back(opticalDepthTable(m));
    // STSV_EMBREE_CONFIG, when set, is Embree's device configuration (rtcNewDevice): `isa=sse2`
    // pins the kernels, whose rounding differs from one instruction set to another, so that a
    // traced buffer is the same on every x86-64 machine (tests/golden pins it so).
    const char* config = std::getenv("STSV_EMBREE_CONFIG");
    m_device = rtcNewDevice(config);
    if (!m_device)
        throw Error("Embree: cannot create a device" +
                    (config ? " with STSV_EMBREE_CONFIG='" + std::string(config) + "'" : std::string()) +
                    " (error " + std::to_string(int(rtcGetDeviceError(nullptr))) + ")");
    m_rtcScene = rtcNewScene(m_device);
    rtcSetSceneFlags(m_rtcScene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(m_rtcScene, RTC_BUILD_QUALITY_HIGH);

    RTCGeometry geometry = rtcNewGeometry(m_device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), scene.positions.size()));
    for (std::size_t i = 0; i < scene.positions.size(); ++i)
        for (int c = 0; c < 3; ++c) vertices[3 * i + c] = scene.positions[i][c];
    auto* indices = static_cast<std::uint32_t*>(
        rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                3 * sizeof(std::uint32_t), scene.triangles.size()));
    for (std::size_t t = 0; t < scene.triangles.size(); ++t)
        for (int c = 0; c < 3; ++c) indices[3 * t + c] = scene.triangles[t][c];
    rtcSetGeometryIntersectFilterFunction(geometry, alphaFilter);
    rtcSetGeometryOccludedFilterFunction(geometry, alphaFilter);
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(m_rtcScene, geometry, 0);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(m_rtcScene);
    checkDevice(m_device, "building the scene");
}

EmbreeScene::~EmbreeScene() {
    if (m_rtcScene) rtcReleaseScene(m_rtcScene);
    if (m_device) rtcReleaseDevice(m_device);
}

bool EmbreeScene::intersect(const Ray& ray, Hit& hit) const {
    return closestHit(ray.origin, ray.direction, 0.0f, 1e30f, hit, true);
}

bool EmbreeScene::intersect(vec3 o, vec3 d, float tNear, float tFar, Hit& hit) const {
    return closestHit(o, d, tNear, tFar, hit, false);
}

bool EmbreeScene::closestHit(vec3 o, vec3 d, float tNear, float tFar, Hit& hit, bool skipTranslucent) const {
    FilterContext ctx{};
    rtcInitIntersectContext(&ctx.rtc);
    ctx.scene = &m_scene;
    ctx.ignoreTriangle = NO_TRIANGLE;
    ctx.skipTranslucent = skipTranslucent;
    RTCRayHit rh = rayHit(o, d, tNear, tFar);
    rtcIntersect1(m_rtcScene, &ctx.rtc, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    hit.t = rh.ray.tfar;
    hit.triangle = rh.hit.primID;
    hit.bary = vec2(rh.hit.u, rh.hit.v);
    return true;
}

/// The shadow segment p → s from tMin to shadowTMax(tMin) (scene/occlusion_rules_dh.h).
static RTCRay shadowRay(vec3 p, vec3 s, float tMin) {
    return rayHit(p, s - p, tMin, shadowTMax(tMin)).ray;
}

bool EmbreeScene::occluded(vec3 p, vec3 s, float tMin, std::uint32_t ignoreTriangle) const {
    FilterContext ctx{};
    rtcInitIntersectContext(&ctx.rtc);
    ctx.scene = &m_scene;
    ctx.ignoreTriangle = ignoreTriangle;
    RTCRay ray = shadowRay(p, s, tMin);
    rtcOccluded1(m_rtcScene, &ctx.rtc, &ray);
    return ray.tfar < 0.0f; // Embree sets tfar to −inf on occlusion
}

std::uint32_t EmbreeScene::countLayers(vec3 p, vec3 s, float tMin, std::uint32_t ignoreTriangle,
                                       std::vector<std::uint32_t>& scratch) const {
    scratch.clear();
    FilterContext ctx{};
    rtcInitIntersectContext(&ctx.rtc);
    ctx.scene = &m_scene;
    ctx.ignoreTriangle = ignoreTriangle;
    ctx.collect = &scratch;
    RTCRay ray = shadowRay(p, s, tMin);
    rtcOccluded1(m_rtcScene, &ctx.rtc, &ray);
    // A primitive referenced by several BVH leaves (spatial splits) may be reported twice.
    std::sort(scratch.begin(), scratch.end());
    return static_cast<std::uint32_t>(std::unique(scratch.begin(), scratch.end()) - scratch.begin());
}

std::uint32_t EmbreeScene::opticalDepth(vec3 p, vec3 s, float tMin, std::uint32_t ignoreTriangle,
                                        std::vector<std::pair<std::uint32_t, std::uint32_t>>& scratch) const {
    scratch.clear();
    FilterContext ctx{};
    rtcInitIntersectContext(&ctx.rtc);
    ctx.scene = &m_scene;
    ctx.ignoreTriangle = ignoreTriangle;
    ctx.crossings = &scratch;
    ctx.depthTables = &m_depthTables;
    RTCRay ray = shadowRay(p, s, tMin);
    rtcOccluded1(m_rtcScene, &ctx.rtc, &ray);
    if (ray.tfar < 0.0f) return OPTICAL_DEPTH_OPAQUE;
    // Each triangle once: a primitive referenced by several BVH leaves (spatial splits) may be
    // reported twice. The sum is modulo 2^32 with a wrap meaning opaque, as the buffers add.
    std::sort(scratch.begin(), scratch.end());
    scratch.erase(std::unique(scratch.begin(), scratch.end()), scratch.end());
    std::uint64_t sum = 0;
    for (const auto& crossing : scratch) sum += crossing.second;
    return sum >= OPTICAL_DEPTH_OPAQUE ? OPTICAL_DEPTH_OPAQUE : std::uint32_t(sum);
}

void EmbreeScene::allHits(vec3 o, vec3 d, float tNear, float tFar, std::vector<Hit>& hits) const {
    hits.clear();
    FilterContext ctx{};
    rtcInitIntersectContext(&ctx.rtc);
    ctx.scene = &m_scene;
    ctx.ignoreTriangle = NO_TRIANGLE;
    ctx.hits = &hits;
    RTCRayHit rh = rayHit(o, d, tNear, tFar);
    // The filter records each candidate and rejects it, so traversal visits them all.
    rtcIntersect1(m_rtcScene, &ctx.rtc, &rh);
    // A primitive referenced by several BVH leaves (spatial splits) may be reported twice.
    std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) { return a.triangle < b.triangle; });
    hits.erase(std::unique(hits.begin(), hits.end(),
                           [](const Hit& a, const Hit& b) { return a.triangle == b.triangle; }),
               hits.end());
}

void EmbreeScene::surfaceCrossings(vec3 o, vec3 d, float tNear, float tFar,
                                   std::vector<SurfaceCrossing>& out) const {
    out.clear();
    FilterContext ctx{};
    rtcInitIntersectContext(&ctx.rtc);
    ctx.scene = &m_scene;
    ctx.ignoreTriangle = NO_TRIANGLE;
    ctx.depthTables = &m_depthTables;
    ctx.surfaces = &out;
    RTCRayHit rh = rayHit(o, d, tNear, tFar);
    // The filter records each candidate and rejects it, so traversal visits them all.
    rtcIntersect1(m_rtcScene, &ctx.rtc, &rh);
    // A primitive referenced by several BVH leaves (spatial splits) may be reported twice; then
    // nearest first, ties by triangle (the order does not depend on the traversal).
    std::sort(out.begin(), out.end(),
              [](const SurfaceCrossing& a, const SurfaceCrossing& b) { return a.triangle < b.triangle; });
    out.erase(std::unique(out.begin(), out.end(),
                          [](const SurfaceCrossing& a, const SurfaceCrossing& b) {
                              return a.triangle == b.triangle;
                          }),
              out.end());
    std::sort(out.begin(), out.end(), [](const SurfaceCrossing& a, const SurfaceCrossing& b) {
        return a.t != b.t ? a.t < b.t : a.triangle < b.triangle;
    });
}

GBuffer EmbreeScene::traceGBuffer(int width, int height) const {
    GBuffer g(width, height);
    parallelForPixels(width, height, [&](int x, int y) {
        const std::size_t i = g.index(x, y);
        Hit hit;
        if (!intersect(primaryRay(m_scene.camera, x, y, width, height), hit)) return;
        // p from the barycentrics, not origin + t·d: it lies on the triangle's plane to round-off.
        g.position[i] = pointOnTriangle(m_scene, hit.triangle, hit.bary);
        g.normal[i] = shadingNormal(m_scene, hit.triangle, m_scene.camera.eye, g.position[i]);
        g.triangle[i] = hit.triangle;
    });
    return g;
}

} // namespace stsv
