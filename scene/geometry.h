// Building blocks shared by the loaders and the procedural scenes: an object-space mesh with its
// own materials, placement into a Scene under a transform, quads and light constructors.
#pragma once

#include "scene/scene.h"

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace stsv {

/// A loaded or generated object before placement: indices, materials and textures are local.
struct MeshData {
    std::vector<vec3> positions;                 ///< object space
    std::vector<vec2> texcoords;                 ///< one per position; v = 0 at texture row 0
    std::vector<uvec3> triangles;                ///< indices into positions
    std::vector<std::uint32_t> triangleMaterial; ///< one per triangle, index into materials
    std::vector<Material> materials;             ///< alphaTexture indexes `textures`
    std::vector<Texture> textures;
    std::size_t skippedFaces = 0;      ///< input faces dropped as degenerate (repeated vertex index)
    std::vector<std::string> warnings; ///< for Scene::warnings (appendMesh adds them)
};

/// Appends `mesh` to `scene` as one Mesh named `name`, positions mapped by `worldFromObject`.
/// Materials and textures are appended too, unless `materialOverride` ≥ 0 (an index into
/// scene.materials) replaces every triangle's material. Returns the index of the new Mesh.
std::size_t appendMesh(Scene& scene, const MeshData& mesh, const mat4& worldFromObject,
                       const std::string& name, int materialOverride = -1);

/// Adds a texture / material to the scene and returns its index.
int addTexture(Scene& scene, Texture texture);
std::uint32_t addMaterial(Scene& scene, Material material);
/// Sets the alpha of `material` from glTF's terms: `mode`, the texture (index into `textures`, −1
/// none) whose alpha byte a gives α = a/255 · factor, and Mask's `cutoff` (α ≥ cutoff blocks).
/// Fills alphaTexture with the binary mask (Mask's rule; a Blend material's stand-in α ≥ 0.5),
/// baking a new texture into `textures` unless the rule is the texture's own alpha byte ≥ 128
/// (factor 1, cutoff 0.5: every scene without these fields keeps its textures as they are).
void setMaterialAlpha(Material& material, std::vector<Texture>& textures, AlphaMode mode, int texture,
                      float factor, float cutoff);

/// A quad in the object's xy plane, centred at the origin, facing +z (counter-clockwise seen from +z):
/// x ∈ [−w/2, w/2], y ∈ [−h/2, h/2]. u runs 0 → uvRepeat.x along +x, v runs 0 → uvRepeat.y from the
/// top edge (+y) down, so a texture appears upright seen from +z. Two triangles, material 0.
MeshData makeQuad(vec2 size, vec2 uvRepeat);

/// A closed tube of segments × sides quads (two triangles each, shared vertices, wound outwards)
/// of `radius` around the closed centre curve `curve(u)`, u ∈ [0, 1). Material 0, named "tube".
MeshData makeTubeMesh(int segments, int sides, float radius, const std::function<vec3(float)>& curve);

/// The (p, q) torus knot as a tube of radius `tube` (object space, about 1.8 × 0.6 × 1.8):
/// 2 · segments · sides triangles, closed, the mesh of the `knot` built-in scene.
MeshData makeTorusKnotMesh(int segments, int sides, float tube, int p = 2, int q = 3);

/// A unit vector perpendicular to `n` (stable choice: world x projected, else world z).
vec3 perpendicularTo(vec3 n);

/// Rectangle light centred at `center` emitting along `normal`, `size` = full edge lengths (world
/// units). axisU points along `tangent` made perpendicular to the normal (any perpendicular if
/// zero or parallel); radius = half-diagonal = length(axisU + axisV).
Light makeRectangleLight(vec3 center, vec3 normal, vec2 size, vec3 radiance, vec3 tangent = vec3(0.0f));
/// Disk light of `radius` around `center`, emitting along `normal`.
Light makeDiskLight(vec3 center, vec3 normal, float radius, vec3 radiance);
/// Sphere light; emits in all directions.
Light makeSphereLight(vec3 center, float radius, vec3 radiance);
/// Distant light seen along `towardsLight` as a disk of `angularRadius` radians; radius = 0.
Light makeDirectionalLight(vec3 towardsLight, float angularRadius, vec3 irradiance);

/// Radiance an area light of area `area` centred at `lightCenter` (emitting along `lightNormal`)
/// needs so that a white-reflecting point p with normal n and diffuse albedo `albedo` sends out
/// `outgoing` (small-light approximation L_o = albedo/π · L · A · cosθ_l · cosθ_p / d²).
float radianceForOutgoing(vec3 lightCenter, vec3 lightNormal, float area, vec3 p, vec3 n, float albedo,
                          float outgoing);

/// A camera looking at `target` from direction `fromTarget` (need not be unit) at the distance
/// where a sphere of `radius` around the target fills the vertical field of view `fovY` (degrees).
Camera frameSphere(vec3 target, float radius, vec3 fromTarget, float fovY = 40.0f);

/// A camera looking at `target` from direction `fromTarget`, at the smallest distance where all
/// eight corners of `box` project inside the central `fill` fraction of a square image
/// (aspect 1; wider images show more). Vulkan clip conventions of camera.h.
Camera frameBox(const Bounds& box, vec3 target, vec3 fromTarget, float fovY = 40.0f, float fill = 0.95f);

/// As frameBox, for a set of points (all of them inside the central `fill` fraction).
Camera framePoints(const std::vector<vec3>& points, vec3 target, vec3 fromTarget, float fovY = 40.0f,
                   float fill = 0.95f);

/// Places a loaded mesh as a whole scene (the `stsv render mesh.obj` case, +y up): the mesh as is,
/// an opaque ground plane just below its lowest point, a square light above, behind and to the
/// side of it sized relative to the mesh, and a camera framing the mesh and its shadow.
Scene makeMeshScene(const MeshData& mesh, const std::string& source);

} // namespace stsv
