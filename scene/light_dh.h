// Light description shared by the scene model, the CPU mirror and the shaders.
#ifndef STSV_SCENE_LIGHT_DH_H
#define STSV_SCENE_LIGHT_DH_H

#include "core/dh.h"

DH_BEGIN

DH_CONST uint LIGHT_RECTANGLE = 0u;   ///< parallelogram centre ± axisU ± axisV, emits along +normal
DH_CONST uint LIGHT_DISK = 1u;        ///< disk of `radius` around `position`, emits along +normal
DH_CONST uint LIGHT_SPHERE = 2u;      ///< sphere of `radius` around `position`, emits everywhere
DH_CONST uint LIGHT_DIRECTIONAL = 3u; ///< distant disk of `angularRadius` seen along +normal

/// std430 layout: 5 × 16 bytes.
struct Light {
    vec3 position;       ///< world units; centre of the light (unused for directional)
    uint type;           ///< LIGHT_*
    vec3 normal;         ///< unit; emitting direction (rect/disk); direction *towards* a directional light
    float radius;        ///< world units; disk and sphere radius, bounding-sphere radius of a rectangle
    vec3 axisU;          ///< world units; rectangle half-extent along its first edge
    float angularRadius; ///< radians; directional lights only
    vec3 axisV;          ///< world units; rectangle half-extent along its second edge
    float pad0;
    vec3 radiance; ///< linear RGB; W·sr⁻¹·m⁻² for area lights, W·m⁻² (irradiance) for directional
    float pad1;
};

#ifdef __cplusplus
DH_STATIC_ASSERT(sizeof(Light) == 80);
#endif

DH_END

#endif // STSV_SCENE_LIGHT_DH_H
