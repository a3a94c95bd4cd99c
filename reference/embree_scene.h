// Embree 3 view of a Scene: the independent oracle (DESIGN §4.7). Primary rays and shadow
// segments both apply the texel rule of scene/occlusion_rules_dh.h, so rays see through holes.
#pragma once

#include "core/gbuffer.h"
#include "scene/camera.h"
#include "scene/scene.h"

#include <embree3/rtcore.h>

#include <utility>
#include <vector>

namespace stsv {

struct Hit {
    float t = 0.0f; ///< ray parameter (world units for unit directions)
    std::uint32_t triangle = NO_TRIANGLE;
    vec2 bary{0.0f}; ///< (b1, b2): weights of the triangle's second and third vertex
};

/// A surface a ray crosses and the light it takes there.
struct SurfaceCrossing {
    float t = 0.0f; ///< ray parameter
    std::uint32_t triangle = NO_TRIANGLE;
    std::uint32_t units = 0; ///< optical-depth units (occlusion_rules_dh.h), OPTICAL_DEPTH_OPAQUE: blocks
};

class EmbreeScene {
  public:
    explicit EmbreeScene(const Scene& scene);
    ~EmbreeScene();
    EmbreeScene(const EmbreeScene&) = delete;
    EmbreeScene& operator=(const EmbreeScene&) = delete;

    /// Closest non-transparent hit along a primary ray, false on a miss: translucent (Blend)
    /// triangles are not receivers, the ray passes through them.
    bool intersect(const Ray& ray, Hit& hit) const;
    /// Closest non-transparent hit of o + t·d with t in [tNear, tFar] (d need not be unit: t is
    /// in units of d); a translucent triangle counts by its binary stand-in (α ≥ 0.5).
    bool intersect(vec3 o, vec3 d, float tNear, float tFar, Hit& hit) const;

    /// True iff the segment p → s, from t = tMin to 1 of (s − p), meets a triangle whose texel
    /// there is opaque. tMin: shadowTMin (scene/occlusion_rules_dh.h) of the pixel's light frame.
    /// `ignoreTriangle` never blocks (self-shadowing rule).
    bool occluded(vec3 p, vec3 s, float tMin, std::uint32_t ignoreTriangle) const;

    /// Number of distinct triangles blocking the segment p → s (its depth complexity), with
    /// the same rules as occluded(). `scratch` is reused storage.
    std::uint32_t countLayers(vec3 p, vec3 s, float tMin, std::uint32_t ignoreTriangle,
                              std::vector<std::uint32_t>& scratch) const;

    /// The optical depth of the segment p → s (occlusion_rules_dh.h units), with the rules of
    /// occluded(): the sum over the distinct translucent triangles it crosses of their texel's
    /// units, OPTICAL_DEPTH_OPAQUE when anything blocks it fully (an opaque or perforated
    /// triangle's blocking texel, a translucent texel with α = 1, or a sum of 2^32 units or more).
    /// `scratch` is reused storage.
    std::uint32_t opticalDepth(vec3 p, vec3 s, float tMin, std::uint32_t ignoreTriangle,
                               std::vector<std::pair<std::uint32_t, std::uint32_t>>& scratch) const;

    /// Every non-transparent hit of o + t·d with t in [tNear, tFar] into `hits` (cleared), in
    /// no particular order, each triangle once (t in units of d). The depth grid of `peel` is
    /// made of them.
    void allHits(vec3 o, vec3 d, float tNear, float tFar, std::vector<Hit>& hits) const;

    /// Every surface of o + t·d with t in [tNear, tFar] that takes light, into `out` (cleared),
    /// nearest first, each triangle once: opaque triangles and a perforated triangle's blocking
    /// texels with OPTICAL_DEPTH_OPAQUE, translucent triangles with their texel's units (those
    /// of 0 units left out). The transmittance functions of `avsm` are made of them.
    void surfaceCrossings(vec3 o, vec3 d, float tNear, float tFar, std::vector<SurfaceCrossing>& out) const;

    /// Visible point per pixel centre through the scene camera (row 0 at the top).
    GBuffer traceGBuffer(int width, int height) const;

    const Scene& scene() const { return m_scene; }

  private:
    bool closestHit(vec3 o, vec3 d, float tNear, float tFar, Hit& hit, bool skipTranslucent) const;

    const Scene& m_scene;
    RTCDevice m_device = nullptr;
    RTCScene m_rtcScene = nullptr;
    std::vector<OpticalDepthTable> m_depthTables; ///< per material
};

} // namespace stsv
