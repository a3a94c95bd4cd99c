// The hulls of a volume family built and drawn in one draw (VK_EXT_mesh_shader; DESIGN §4.2, §5):
// the task and mesh shaders of stsv.task/stsv.mesh and wedge.task/wedge.mesh, which define
// before including it what the compute hull pass's family file defines (stsv_hull_items.glsl,
// wedge_hull_items.glsl: hullItem, hullVolume, HULL_RECORD) and, for the mesh stage, the stats
// buffer `stats` (GpuHullCounts first), and after including it the per-primitive outputs with
// `void hullMeshPrimitive(uint p, HULL_RECORD r)`, which writes them.
//
// Task stage (HULL_TASK_STAGE): a workgroup takes HULL_TASK_ITEMS items and culls them with the
// same tests as the compute hull pass (hullItem, then hullVolume: the light planes, the receivers'
// box); the survivors, in item order, go to ⌈survivors / HULL_MESH_VOLUMES⌉ mesh workgroups.
// Mesh stage: an invocation per survivor builds its volume, clips its hull (clip_box_dh.h, in
// shared memory) and emits the faces the rasteriser keeps (hull_faces.glsl) as fans, each
// triangle with its volume's record as per-primitive outputs — no buffer, no indirect draw.
#ifndef STSV_SHADERS_HULL_MESH_GLSL
#define STSV_SHADERS_HULL_MESH_GLSL

#extension GL_EXT_mesh_shader : require

#ifndef HULL_TASK_ITEMS
#define HULL_TASK_ITEMS 32
#endif
#ifndef HULL_MESH_VOLUMES
#define HULL_MESH_VOLUMES 2
#endif

struct HullTaskPayload {
    uint count;                   ///< survivors
    uint items[HULL_TASK_ITEMS]; ///< their items, in item order
};
taskPayloadSharedEXT HullTaskPayload payload;

#ifdef HULL_TASK_STAGE

layout(local_size_x = HULL_TASK_ITEMS) in;

shared uint taskSurvives[HULL_TASK_ITEMS];

void main() {
    // Workgroups cover the items row by row (render/vulkan/gpu_hulls.cpp recordMeshHullDraw).
    uint group = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint item = group * uint(HULL_TASK_ITEMS) + gl_LocalInvocationIndex;
    uint index;
    uint side;
    bool survives = hullItem(item, index, side);
    if (survives) {
        StsvHullSetup h;
        HULL_RECORD r;
        survives = hullVolume(index, side, h, r);
    }
    taskSurvives[gl_LocalInvocationIndex] = survives ? 1u : 0u;
    barrier();
    // Compacted in item order, so that the draw's primitive order, and a blend's sum, is the same
    // in every frame.
    uint before = 0u;
    uint count = 0u;
    for (uint i = 0u; i < uint(HULL_TASK_ITEMS); ++i) {
        before += i < gl_LocalInvocationIndex ? taskSurvives[i] : 0u;
        count += taskSurvives[i];
    }
    if (survives) payload.items[before] = item;
    if (gl_LocalInvocationIndex == 0u) payload.count = count;
    EmitMeshTasksEXT((count + uint(HULL_MESH_VOLUMES) - 1u) / uint(HULL_MESH_VOLUMES), 1u, 1u);
}

#else // the mesh stage

/// A hull's corners and triangles, at most: a convex polyhedron of F ≤ CLIP_MAX_FACES faces has
/// E ≤ 3F − 6 edges, so its faces hold 2E ≤ 6F − 12 corners and 2E − 2F ≤ 4F − 12 fan
/// triangles (CLIP_MAX_TRIANGLES). A hull that rounding made larger is counted as an overflow
/// and not drawn; the host turns the count into an error.
const uint HULL_MESH_MAX_CORNERS = 6u * CLIP_MAX_FACES - 12u;

layout(local_size_x = HULL_MESH_VOLUMES) in;
layout(triangles, max_vertices = HULL_MESH_VOLUMES * HULL_MESH_MAX_CORNERS,
       max_primitives = HULL_MESH_VOLUMES * CLIP_MAX_TRIANGLES) out;

// Only gl_Position: the implicit per-vertex and per-primitive blocks hold built-ins (the
// primitive shading rate) whose capability the device was not created with
// (VUID-VkShaderModuleCreateInfo-pCode-01091).
out gl_MeshPerVertexEXT {
    vec4 gl_Position;
} gl_MeshVerticesEXT[];

/// Writes primitive p's per-primitive outputs from its volume's record (after the include).
void hullMeshPrimitive(uint p, HULL_RECORD r);

shared uint meshCorners[HULL_MESH_VOLUMES];
shared uint meshTriangles[HULL_MESH_VOLUMES];

void main() {
    uint slot = gl_WorkGroupID.x * uint(HULL_MESH_VOLUMES) + gl_LocalInvocationIndex;
    ClippedBox hull;
    hull.faceCount = 0u;
    StsvHullSetup h;
    HULL_RECORD r;
    uint drawn = 0u;
    uint triangles = 0u;
    uint corners = 0u;
    uint index;
    uint side;
    if (slot < payload.count && hullItem(payload.items[slot], index, side) && hullVolume(index, side, h, r)) {
        hull = clipBox(h.lo, h.hi, h.planes, h.count, h.minCut);
        drawn = hullDrawnFaces(hull, h, triangles, corners);
    }
    if (triangles > 0u) {
        atomicAdd(stats[pc.light].hull.volumes, 1u);
        atomicAdd(stats[pc.light].hull.triangles, triangles);
        if (triangles > CLIP_MAX_TRIANGLES || corners > HULL_MESH_MAX_CORNERS) {
            atomicAdd(stats[pc.light].hull.overflow, 1u);
            drawn = 0u;
            triangles = 0u;
            corners = 0u;
        }
    }
    meshCorners[gl_LocalInvocationIndex] = corners;
    meshTriangles[gl_LocalInvocationIndex] = triangles;
    barrier();
    uint corner = 0u;
    uint triangle = 0u;
    uint cornerCount = 0u;
    uint triangleCount = 0u;
    for (uint i = 0u; i < uint(HULL_MESH_VOLUMES); ++i) {
        corner += i < gl_LocalInvocationIndex ? meshCorners[i] : 0u;
        triangle += i < gl_LocalInvocationIndex ? meshTriangles[i] : 0u;
        cornerCount += meshCorners[i];
        triangleCount += meshTriangles[i];
    }
    SetMeshOutputsEXT(cornerCount, triangleCount);
    // Each drawn face as a fan over its own corners, counter-clockwise seen from outside.
    for (uint f = 0u; f < hull.faceCount; ++f) {
        if ((drawn & (1u << f)) == 0u) continue;
        uint o = f * CLIP_MAX_FACE_VERTICES;
        uint n = hull.count[f];
        for (uint i = 0u; i < n; ++i)
            gl_MeshVerticesEXT[corner + i].gl_Position =
                hullClipPosition(hullWorldCorner(CLIP_CORNER(hull, o + i), h.origin, h.scale));
        for (uint i = 1u; i + 1u < n; ++i) {
            gl_PrimitiveTriangleIndicesEXT[triangle] = uvec3(corner, corner + i, corner + i + 1u);
            hullMeshPrimitive(triangle, r);
            triangle += 1u;
        }
        corner += n;
    }
}

#endif

#endif
