// Edge adjacency of opaque meshes for silhouette extraction (DESIGN §4.5): vertices welded by
// exact position, then every undirected edge with all the triangles that use it — one (open
// edge), two (manifold) or more (non-manifold). The DCS and PW math uses the side of each face's
// third vertex, so inconsistently oriented input works (EdgeFace::forward, each face's winding
// along the edge, only counts the inconsistent edges).
#pragma once

#include "core/dh.h"
#include "scene/scene.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace stsv {

/// One triangle incident to an edge.
struct EdgeFace {
    std::uint32_t triangle; ///< scene triangle index
    std::uint32_t opposite; ///< welded vertex index of the triangle's third vertex
    bool forward;           ///< the triangle runs v0 → v1 of the edge (false: v1 → v0)
};

struct MeshEdge {
    std::uint32_t v0, v1;    ///< welded vertex indices, v0 < v1
    std::uint32_t firstFace; ///< into EdgeAdjacency::faces
    std::uint32_t faceCount; ///< 1 open, 2 manifold, > 2 non-manifold
};

struct EdgeAdjacency {
    std::vector<vec3> positions;             ///< world units; one per welded vertex
    std::vector<std::uint32_t> weldedVertex; ///< scene vertex → welded vertex (UINT32_MAX if unused)
    std::vector<MeshEdge> edges;             ///< sorted by (v0, v1)
    std::vector<EdgeFace> faces;             ///< grouped per edge
    std::size_t triangles = 0;               ///< triangles taken in
    std::size_t degenerateSkipped = 0;       ///< triangles with two equal welded vertices (no edges)
    std::size_t openEdges = 0;
    std::size_t manifoldEdges = 0;
    std::size_t nonManifoldEdges = 0;
    /// Manifold edges whose two faces run it in the same direction (inconsistent winding).
    std::size_t inconsistentEdges = 0;
};

/// Builds the adjacency of the scene triangles accepted by `include` (all when empty).
/// Welding is by exact position (−0 = +0): loaders and generators duplicate seam vertices with
/// bit-identical coordinates, and exact welding never merges distinct nearby vertices (an
/// epsilon would, non-transitively, and change topology). Adjacency across edges is by welded
/// vertex pairs, so it is immune to OpenMesh's duplication of non-manifold vertices.
EdgeAdjacency buildEdgeAdjacency(const Scene& scene, const std::function<bool(std::size_t)>& include = {});

/// Indices of the edges that can be silhouettes for some point of a light inside `lightSphere`
/// (centre xyz, radius w): open and non-manifold edges always; a manifold edge unless the whole
/// sphere lies strictly on the same side (front or back) of both its faces' planes
/// (dcsPotentialSilhouette of wedges/dcs_dh.h, the test wedges/shaders/wedge.geom runs).
std::vector<std::uint32_t> potentialSilhouetteEdges(const EdgeAdjacency& adjacency, vec4 lightSphere);

/// EdgeCarriers' value for an edge without a carrier.
inline constexpr std::uint32_t NO_CARRIER = 0xffffffffu;

/// The carrier of every edge: the scene triangle of its first face that is not degenerate for
/// the volumes (stsvTriangleIsDegenerate), whose STSV volumes and light planes bound the edge's
/// wedge in the DCS and PW passes of both backends; NO_CARRIER for an edge whose faces are all
/// degenerate (their third vertices lie on the edge's line, so k_e = 0 for every p: no wedge).
/// `scene` is the one the adjacency was built from.
std::vector<std::uint32_t> edgeCarriers(const EdgeAdjacency& adjacency, const Scene& scene);

} // namespace stsv
