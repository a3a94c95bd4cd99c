#include "render/renderer.h"

#include "core/error.h"
#include "render/cpu/cpu_renderer.h"
#include "render/vulkan/gpu_renderer.h"

namespace stsv {

std::unique_ptr<FrameRenderer> makeRenderer(const Scene& scene, const RenderOptions& options) {
    validate(options);
    const MethodInfo& method = methodInfo(options.method);
    if (!method.implementedOn(options.backend))
        throw UsageError("method " + method.name + " does not run on " + toString(options.backend) +
                         " (it runs on " + toString(method.backends.front()) + ")");
    if (options.backend == Backend::Vulkan) return std::make_unique<VulkanRenderer>(scene, options);
    return makeCpuRenderer(scene, options);
}

Frame renderFrame(const Scene& scene, const RenderOptions& options) {
    return makeRenderer(scene, options)->render();
}

} // namespace stsv
