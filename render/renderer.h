// A renderer of either backend from the options: the CPU renderer (render/cpu) or the Vulkan one
// (render/vulkan). Code that wants one backend only links that backend's library instead.
#pragma once

#include "render/frame.h"

#include <memory>

namespace stsv {

/// The renderer for options.backend; UsageError when the method's row does not list that
/// backend. `scene` must outlive it.
std::unique_ptr<FrameRenderer> makeRenderer(const Scene& scene, const RenderOptions& options);

/// One frame with a fresh renderer (start-up included in the call, not in frame_ms).
Frame renderFrame(const Scene& scene, const RenderOptions& options);

} // namespace stsv
