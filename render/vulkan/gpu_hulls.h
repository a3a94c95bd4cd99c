// Volumes drawn as their hulls (DESIGN §4.2, §5): a compute pass builds each volume, clips the
// scene box by its planes and its light's (volumes/clip_box_dh.h) and appends the polyhedron's
// triangles and the volume's record; the volume pass then draws them with one indirect draw of
// hull.vert, its fragment reading the record by index. The STSV pass (stsv_hull.comp) and the
// wedge pass (wedge_hull.comp) use the same buffers one after the other.
#pragma once

#include "gpu/buffer.h"
#include "gpu/pipeline.h"
#include "render/vulkan/gpu_frame_resources.h"
#include "render/vulkan/gpu_pass.h"
#include "render/vulkan/gpu_volumes_dh.h"
#include "volumes/clip_box_dh.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace stsv {

class CommandBuffer;
class HullPass;

/// What builds the volumes the STSV and wedge passes rasterise (ExtrusionStage, resolved for the
/// device).
enum class VolumeGeometry {
    GeometryShaderPrism, ///< stsv.vert + stsv.geom, wedge.geom: the ten-vertex prisms
    MeshShaderHull,      ///< stsv.task + stsv.mesh, wedge.task + wedge.mesh: the hulls, in the draw
    ComputeHull,         ///< stsv_hull.comp, wedge_hull.comp, then hull.vert: the hulls, drawn indirect
};

const char* toString(VolumeGeometry geometry);

/// What the hull passes append and the draws read: the indirect arguments and counts, the
/// records and the vertices. Sized at start-up by a run of the hull passes (resize), so a
/// frame's exact needs; 1-element stand-ins before that.
class HullResources {
  public:
    explicit HullResources(const Device& device);

    /// The bindings these resources add to a volume family's set (gpu_volumes_dh.h).
    static std::vector<DescriptorBinding> bindings();
    void writeDescriptors(DescriptorSet& set) const;
    /// Room for `records` records and `triangles` hull triangles (at least one of each).
    void resize(std::uint64_t records, std::uint64_t triangles);
    /// Runs `passes` once per light into the 1-element stand-ins: they count every volume and
    /// triangle in their family's stats (GpuHullCounts, zeroed first) while writing none, and
    /// the buffers get exactly the largest pass's needs (the passes are deterministic: every
    /// frame appends the same counts). The family stats are left dirty (the frame clears them)
    /// and the descriptors must be written again.
    void size(PassRecorder& recorder, CommandBuffer& commands, std::size_t lights,
              const std::vector<const HullPass*>& passes);
    /// A hull pass writes nothing past the buffers sized at start-up; a frame that needed more
    /// is wrong, so it is an error, not a picture.
    void checkCapacity(std::size_t light, const char* pass, std::uint64_t volumes,
                       std::uint64_t triangles) const;
    /// A family's hull counts of light `light` after a frame drawn through `geometry`: an error
    /// where the compute path outgrew these buffers or the mesh path met a hull larger than a
    /// workgroup emits (drawn by neither), else `hull_volumes` and `hull_triangles` into `out`
    /// (both hull paths; the prisms have no hulls).
    void reportCounts(VolumeGeometry geometry, std::size_t light, const char* pass,
                      const GpuHullCounts& counts, nlohmann::json& out) const;

    Buffer draw;     ///< GpuHullDraw
    Buffer records;  ///< GPU_HULL_RECORD_TEXELS uvec4 per record, written as storage, read as texels
    Buffer vertices; ///< uvec4 per hull vertex, written as storage, read as texels
    BufferView recordTexels;
    BufferView vertexTexels;

    /// The draw's accesses, for a volume pass that draws the hulls.
    void declareDrawReads(PassAccesses& accesses) const;
    /// The indirect draw of the hulls (inside the pass's rendering).
    void recordDraw(VkCommandBuffer cmd) const;

  private:
    const Device* m_device;
    std::uint64_t m_recordCapacity = 0;
    std::uint64_t m_triangleCapacity = 0;
};

/// One hull compute pass for one light: `shader` (stsv_hull.comp, wedge_hull.comp) over the
/// sides of `items` (triangles, carrier faces), side 0 of every item first, HULL_ITEMS_PER_THREAD
/// sides a thread (a workgroup queues those with a volume, then clips them), counting them in the
/// GpuHullCounts that begin its family's stats. The HullResources' draw arguments must be zeroed
/// before (HullResources::draw). `writes`: the family's buffers it writes besides (the STSV
/// walk's item table).
class HullPass final : public GpuPass {
  public:
    HullPass(const Device& device, const std::string& shader, const std::vector<ShaderDefine>& defines,
             std::uint32_t items, std::uint32_t pushFlags, HullResources& hulls,
             const FamilyDescriptors& descriptors, std::vector<const Buffer*> writes = {});
    /// The family whose stats the pass counts in.
    const FamilyDescriptors& family() const { return *m_descriptors; }

    PassAccesses accesses(std::size_t light) const override;
    void record(VkCommandBuffer cmd, std::size_t light) const override;

  private:
    HullResources* m_hulls;
    const FamilyDescriptors* m_descriptors;
    std::vector<const Buffer*> m_writes;
    std::uint32_t m_items;
    std::uint32_t m_pushFlags;
    std::uint32_t m_threadsPerGroup;
    std::uint32_t m_itemsPerThread;
    Pipeline m_pipeline;
};

/// The mesh path of a family's hulls (VK_EXT_mesh_shader; render/shaders/hull_mesh.glsl): the task and
/// mesh stages of `shader` ("volumes/shaders/stsv", "wedges/shaders/wedge": its .task and .mesh), which cull,
/// build, clip and emit the hulls within the volume pass's draw. A mesh workgroup takes as many volumes as
/// the device's mesh output and shared-memory limits hold (HULL_MESH_VOLUMES).
std::vector<ShaderStage> meshHullStages(const Device& device, const std::string& shader,
                                        const std::vector<ShaderDefine>& defines);
/// The draw of the mesh path over the sides of `items` items (triangles, carrier faces).
void recordMeshHullDraw(const Device& device, VkCommandBuffer cmd, std::uint32_t items);
/// The stages in which a volume pass drawn through `geometry` counts in its family's stats: the
/// fragments, and the task and mesh shaders that count the hulls they emit.
constexpr VkPipelineStageFlags2 volumeStatsStages(VolumeGeometry geometry) {
    return VK_PIPELINE_STAGE_2_FRAGMENT_SHADER_BIT |
           (geometry == VolumeGeometry::MeshShaderHull
                ? VK_PIPELINE_STAGE_2_TASK_SHADER_BIT_EXT | VK_PIPELINE_STAGE_2_MESH_SHADER_BIT_EXT
                : VkPipelineStageFlags2(0));
}

} // namespace stsv
