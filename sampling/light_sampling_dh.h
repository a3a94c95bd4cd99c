// Light frames, per-pixel sample points and the Monte-Carlo direct-lighting term, shared by
// every method (CPU mirror, shaders, Embree reference) so that light sample k of pixel
// (x, y) is the same point everywhere (DESIGN §4.1). Compiles as C++ and GLSL (core/dh.h).
//
// A pixel's sample k:
//   u  = pattern point k of the pixel's interleaved set (SamplePlan, in [0,1)², multiple of 2⁻²⁴)
//   u' = decorrelate(u, pixel, seed)           per-pixel Cranley–Patterson rotation (optional)
//   ab = domainPoint(u', frame.domain)          [−1,1]² or the unit disk (Shirley–Chiu)
//   s  = frame.center + ab.x·frame.T + ab.y·frame.B
// The rotation is a toroidal shift done in 24-bit fixed point, so it is exact: it preserves
// every toroidal distance of the pattern, the number of points in every toroidally shifted
// stratum / elementary interval, and the uniform density of each point (unbiased estimates).
// It acts before the domain map, so one transform serves squares and disks.
#ifndef STSV_SAMPLING_LIGHT_SAMPLING_DH_H
#define STSV_SAMPLING_LIGHT_SAMPLING_DH_H

#include "core/dh.h"
#include "scene/light_dh.h"

DH_BEGIN

DH_CONST uint DOMAIN_SQUARE = 0u; ///< (a, b) ∈ [−1,1]²
DH_CONST uint DOMAIN_DISK = 1u;   ///< (a, b) in the closed unit disk

DH_CONST float SAMPLING_PI = 3.14159265358979f;
DH_CONST float SAMPLING_FIXED_ONE = 16777216.0f; ///< 2^24: pattern points are multiples of 1/2^24
DH_CONST uint SAMPLING_FIXED_MASK = 0xFFFFFFu;

/// The light type the functions below branch on. A shader compiled for one light type defines
/// FIXED_LIGHT_TYPE (a LIGHT_* value) so that these branches fold at compile time (on SIMD CPU
/// drivers a per-lane branch executes both sides); C++ never defines it.
#ifdef FIXED_LIGHT_TYPE
#define SAMPLING_LIGHT_TYPE(light) (FIXED_LIGHT_TYPE)
#else
#define SAMPLING_LIGHT_TYPE(light) ((light).type)
#endif

/// Light samples of one receiver point: s = center + a·T + b·B. std430: 3 × 16 bytes.
struct LightFrame {
    vec3 center; ///< world units
    uint domain; ///< DOMAIN_*
    vec3 T;      ///< world units; half-extent along the first axis
    float pad0;
    vec3 B; ///< world units; half-extent along the second axis
    float pad1;
};

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(LightFrame) == 48);
#endif

/// Orthonormal b1, b2 with (b1, b2, n) right-handed, for unit n. Duff et al. 2017, "Building
/// an Orthonormal Basis, Revisited" (JCGT 6(1)), Listing 3: continuous except across n.z = 0.
DH_FUNC void orthonormalBasis(vec3 n, DH_OUT(vec3) b1, DH_OUT(vec3) b2) {
    float sgn = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sgn + n.z);
    float b = n.x * n.y * a;
    b1 = vec3(1.0f + sgn * n.x * n.x * a, sgn * b, -sgn * n.x);
    b2 = vec3(b, sgn + n.y * n.y * a, -n.y);
}

/// The domain of `light`'s frames, whatever the receiver: the rectangle's square, else a disk.
DH_FUNC uint lightDomain(Light light) {
    return SAMPLING_LIGHT_TYPE(light) == LIGHT_RECTANGLE ? DOMAIN_SQUARE : DOMAIN_DISK;
}

/// The frame of `light` seen from receiver point p (world units). Rectangle: its own axes,
/// square domain. Disk: basis of its plane scaled by the radius. Sphere: the disk of `radius`
/// through the centre, perpendicular to centre − p (its silhouette as seen from p, as in DCS).
/// Directional: a disk at `farDistance` from p along the light direction, of radius
/// farDistance·tan(angularRadius).
DH_FUNC LightFrame lightFrame(Light light, vec3 p, float farDistance) {
    LightFrame f;
    f.pad0 = 0.0f;
    f.pad1 = 0.0f;
    f.domain = lightDomain(light);
    if (SAMPLING_LIGHT_TYPE(light) == LIGHT_RECTANGLE) {
        f.center = light.position;
        f.T = light.axisU;
        f.B = light.axisV;
        return f;
    }
    vec3 axis = light.normal;
    vec3 center = light.position;
    float extent = light.radius;
    if (SAMPLING_LIGHT_TYPE(light) == LIGHT_SPHERE) {
        vec3 d = light.position - p;
        float len = length(d);
        axis = len > 0.0f ? d / len : vec3(0.0f, 0.0f, 1.0f);
    } else if (SAMPLING_LIGHT_TYPE(light) == LIGHT_DIRECTIONAL) {
        center = p + light.normal * farDistance;
        extent = farDistance * tan(light.angularRadius);
    }
    vec3 b1;
    vec3 b2;
    orthonormalBasis(axis, b1, b2);
    f.center = center;
    f.T = b1 * extent;
    f.B = b2 * extent;
    return f;
}

/// True when every light sample of `light` lies in one square, whatever the receiver: a
/// rectangle's frame, or the square around a disk (c ± T ± B, world units). Sphere and directional
/// lights turn their frame towards each receiver.
DH_FUNC bool lightSampleSquare(Light light, float farDistance, DH_OUT(LightFrame) square) {
    square = lightFrame(light, vec3(0.0f), farDistance);
    return SAMPLING_LIGHT_TYPE(light) == LIGHT_RECTANGLE || SAMPLING_LIGHT_TYPE(light) == LIGHT_DISK;
}

/// Integer hash of Jarzynski & Olano 2020 ("Hash Functions for GPU Rendering", PCG variant).
DH_FUNC uint pcgHash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/// Seeded hash of a pixel (chained PCG hashes, no collisions along rows or columns).
DH_FUNC uint pixelHash(uvec2 pixel, uint seed) {
    return pcgHash(pixel.x + pcgHash(pixel.y + pcgHash(seed)));
}

/// The pixel's toroidal offset in 24-bit fixed point (each component in [0, 2^24)).
DH_FUNC uvec2 decorrelationOffset(uvec2 pixel, uint seed) {
    uint h = pixelHash(pixel, seed);
    return uvec2(h >> 8u, pcgHash(h ^ 0x9e3779b9u) >> 8u);
}

/// Per-pixel "random rotation" of the pattern (STSV paper §4.1, DESIGN §4.1): a Cranley–
/// Patterson rotation u' = (u + offset(pixel)) mod 1 in exact 24-bit fixed point. u01 must be
/// in [0,1) (pattern points are; other values are truncated to 2⁻²⁴).
DH_FUNC vec2 decorrelateBy(vec2 u01, uvec2 offset) {
    uvec2 q = uvec2(u01 * SAMPLING_FIXED_ONE);
    q = (q + offset) & uvec2(SAMPLING_FIXED_MASK);
    return vec2(q) * (1.0f / SAMPLING_FIXED_ONE);
}

/// decorrelateBy the pixel's offset (decorrelationOffset).
DH_FUNC vec2 decorrelate(vec2 u01, uvec2 pixel, uint seed) {
    return decorrelateBy(u01, decorrelationOffset(pixel, seed));
}

/// [0,1)² → [−1,1]² (square) or the unit disk by the concentric map of Shirley & Chiu 1997,
/// which is area-preserving (constant Jacobian π/4 from [−1,1]²), so stratification survives.
DH_FUNC vec2 domainPoint(vec2 u01, uint domain) {
    vec2 q = 2.0f * u01 - vec2(1.0f);
    if (domain == DOMAIN_SQUARE) return q;
    if (q.x == 0.0f && q.y == 0.0f) return vec2(0.0f);
    float r;
    float theta;
    if (abs(q.x) > abs(q.y)) {
        r = q.x;
        theta = (0.25f * SAMPLING_PI) * (q.y / q.x);
    } else {
        r = q.y;
        theta = 0.5f * SAMPLING_PI - (0.25f * SAMPLING_PI) * (q.x / q.y);
    }
    return r * vec2(cos(theta), sin(theta));
}

/// Frame coordinates (a, b) of a pixel's sample: the single definition used by every method.
DH_FUNC vec2 samplePoint(vec2 patternPoint, uvec2 pixel, uint seed, bool decorrelated, uint domain) {
    vec2 u = decorrelated ? decorrelate(patternPoint, pixel, seed) : patternPoint;
    return domainPoint(u, domain);
}

/// Interleaved sampling (Keller & Heidrich 2001): the pixel's set among K×K.
DH_FUNC uint interleaveSet(uvec2 pixel, uint interleave) {
    return (pixel.y % interleave) * interleave + (pixel.x % interleave);
}

/// World position of frame point (a, b).
DH_FUNC vec3 lightSamplePosition(LightFrame f, vec2 ab) {
    return f.center + ab.x * f.T + ab.y * f.B;
}

/// One term of the direct-lighting estimate (DESIGN §4.4, "Direct MC" of the paper):
///   Lo(p) = albedo/π · (1/N) Σ_k sampleContribution_k · V_k.
/// Area lights: Le·cosθp·cosθl·A / |s − p|² (A = the frame domain's world area); the sphere
/// uses its silhouette disk, A = πr², cosθl = 1; directional: E·cosθp (radiance holds the
/// irradiance E). Rectangles and disks emit along +normal only. cosθp is clamped at 0: a
/// double-sided receiver flips n towards the light beforehand (the caller's job).
DH_FUNC vec3 sampleContribution(Light light, LightFrame f, vec3 p, vec3 n, vec3 s) {
    vec3 d = s - p;
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0f)) return vec3(0.0f);
    vec3 wi = d * inversesqrt(dist2);
    float cosP = max(dot(n, wi), 0.0f);
    if (SAMPLING_LIGHT_TYPE(light) == LIGHT_DIRECTIONAL) return light.radiance * cosP;
    float frameArea = length(cross(f.T, f.B)); // |T × B|: world area of the unit-square patch
    float area = f.domain == DOMAIN_SQUARE ? 4.0f * frameArea : SAMPLING_PI * frameArea;
    float cosL = SAMPLING_LIGHT_TYPE(light) == LIGHT_SPHERE ? 1.0f : max(-dot(light.normal, wi), 0.0f);
    return light.radiance * (cosP * cosL * area / dist2);
}

/// True when receiver p (world units) with shading normal n faces `light`, whose frame at p is f
/// (lightFrame(light, p, farDistance)): some point s of the frame's domain has n·(s − p) > 0 and,
/// for rectangles and disks, which emit along +normal only, p lies strictly in front of the
/// light's plane (normal·(p − centre) > 0). Otherwise sampleContribution is 0 for every sample s
/// (cosθp or cosθl clamped to 0), so visibility changes nothing in the lit image. The largest
/// n·(s − p) over the domain is n·(centre − p) plus its reach |n·T| + |n·B| over the square
/// (a corner) or √((n·T)² + (n·B)²) over the disk. So a rectangle or disk counts where any part of
/// it is in front of the receiver's plane; a sphere where its silhouette disk, which every method
/// samples, is (a receiver whose plane cuts only the cap nearer to p gets no light from those
/// samples); a directional light where its cone of angularRadius around the direction is.
/// Receivers edge-on to a light's plane, or whose plane only touches the light, do not count.
DH_FUNC bool receiverFacesLight(Light light, LightFrame f, vec3 p, vec3 n) {
    if ((SAMPLING_LIGHT_TYPE(light) == LIGHT_RECTANGLE || SAMPLING_LIGHT_TYPE(light) == LIGHT_DISK) &&
        !(dot(light.normal, p - f.center) > 0.0f))
        return false;
    float nt = dot(n, f.T);
    float nb = dot(n, f.B);
    float reach = f.domain == DOMAIN_SQUARE ? abs(nt) + abs(nb) : sqrt(nt * nt + nb * nb);
    return dot(n, f.center - p) + reach > 0.0f;
}

DH_END

#endif // STSV_SAMPLING_LIGHT_SAMPLING_DH_H
