// The Vulkan backend of a frame (DESIGN §5, STSV paper Algorithm 2): G-buffer, per light one
// draw of all S-triangles through the STSV extrusion (geometry shader, or mesh shader where the
// device has VK_EXT_mesh_shader) into the light-sample buffer, then the resolve into visibility
// and Monte-Carlo direct lighting. Fills the same Frame as the CPU backend.
#pragma once

#include "render/frame.h"

#include <cstddef>
#include <memory>
#include <vector>

namespace stsv {

class Device;
struct DeviceInfo;

struct VulkanRendererConfig {
    /// Render on this device (it must outlive the renderer) instead of creating one from
    /// RenderOptions::device / RenderOptions::validation. Tests share one validated device.
    Device* device = nullptr;
    /// The fragments the STSV hull draw and the DCS wedge draw may list for their sample passes
    /// at first (0: two a pixel); a frame that needs more grows the list and renders again.
    /// Tests make it small.
    std::uint64_t deferredCapacity = 0;
    /// The pairs one list of the cluster walk (STSV's and DCS's) may hold at most (0: what a storage buffer
    /// binding of the device addresses); past it the walk takes the tiles in parts. Tests make
    /// it small.
    std::uint64_t clusterListLimit = 0;
    /// The fragments the list for the sample passes may hold at most (0: MAX_DEFERRED_FRAGMENTS);
    /// past it the walk takes the tiles in parts (the hull and geometry paths stop with an
    /// error). Tests make it small.
    std::uint64_t deferredLimit = 0;
};

/// Payload bytes of one light's sample buffer for `options` without rendering: N·W·H/8 for
/// bitmasks (8 MiB at 1024² × 64, the STSV paper's §5.1 figure), 2·N·W·H for 16-bit counters.
std::size_t lightSampleBufferBytes(const RenderOptions& options);

/// The GPU camera's near plane as a fraction of the scene's reach from the eye (the distance to
/// the box's centre plus its radius). The projection has no far plane and a reversed float depth
/// (scene/camera.h), so the near plane costs no precision: the rasteriser sees what the ray
/// tracer sees except surfaces within this fraction of the reach from the eye (3 mm of a 30 km
/// scene), which the G-buffer clips and Embree's primary rays hit.
constexpr float GPU_NEAR_FRACTION = 1e-7f;

/// The GPU camera's near plane distance, world units: GPU_NEAR_FRACTION of the scene's reach.
float gpuNearPlane(const Scene& scene);

/// clipFromViewReversedInfinite(gpuNearPlane)·viewFromWorld for a width × height image
/// (scene/camera.h): depth 1 at the near plane, toward 0 at infinity.
mat4 gpuClipFromWorld(const Scene& scene, int width, int height);

/// Start-up in the constructor: device, shader compilation, pipelines, scene uploads, images.
/// render() records, submits and reads back one frame. `scene` must outlive the renderer.
/// Stats: "frame_ms" (wall time of render(), readback included), "gpu_ms" (submit to fence),
/// "passes" (GPU timestamps: gbuffer, light<i>/stsv_clusters or stsv, light<i>/{dcs_,pw_}center,
/// clusters or wedges, light<i>/fold, light<i>/resolve, ambient without lights, copy = all
/// outputs into one host-visible buffer; host: readback = unpacking it into the Frame),
/// "stsv"[i] {"path", "fragments", "inside_fragments", "samples_tested"} counted by atomics in
/// the shaders (the walk's or the draw's: docs/methods.md; with the walk or hulls also
/// "listed_fragments", those listed for stsv_samples.comp, and "deferred_fragments", those of
/// them inside); for methods with an opaque technique "wedges"[i] {"edges", "path",
/// "fragments", "silhouette_fragments", DCS: "listed_fragments" (those listed for
/// wedge_samples.comp), "samples_tested", "center" {"nodes" (of the tree D(r) is counted
/// through), "node_visits", "triangle_tests" (dcs_center.comp)};
/// "light_sample_buffer_bytes", "startup_ms", "gpu" {device, extrusion: "cluster walk" where
/// the families walk, else the volume stage}.
class VulkanRenderer final : public FrameRenderer {
  public:
    VulkanRenderer(const Scene& scene, const RenderOptions& options, const VulkanRendererConfig& config = {});
    ~VulkanRenderer() override;
    VulkanRenderer(const VulkanRenderer&) = delete;
    VulkanRenderer& operator=(const VulkanRenderer&) = delete;

    Frame render() override;

    const Device& device() const;
    bool usesMeshShader() const;

  private:
    struct Impl;
    std::unique_ptr<Impl> m_impl;
};

/// The --extrusion stages a device runs: hull always, geometry and mesh where it has those
/// shaders (`stsv info` lists them).
std::vector<ExtrusionStage> offeredExtrusions(const DeviceInfo& info);

} // namespace stsv
