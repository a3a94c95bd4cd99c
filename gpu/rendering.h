// Dynamic rendering (Vulkan 1.3): begin/end a pass on Image attachments.
#pragma once

#include "gpu/vulkan.h"

#include <optional>
#include <span>

namespace stsv {

class Image;

struct ColorTarget {
    Image* image = nullptr;
    bool clear = true;              ///< clear to `clearValue`, else load
    VkClearColorValue clearValue{}; ///< .uint32 for integer formats, .float32 otherwise
};

struct DepthTarget {
    Image* image = nullptr;
    bool clear = true;
    float clearDepth = 1.0f;
    bool readOnly = false; ///< DEPTH_READ_ONLY_OPTIMAL layout (test without write)
};

/// Transitions the attachments, begins rendering over their common extent and sets the
/// viewport (y down, depth 0..1) and scissor to the whole extent.
void beginRendering(VkCommandBuffer cmd, std::span<const ColorTarget> colors,
                    std::optional<DepthTarget> depth = std::nullopt);
/// Begins rendering over `extent` without attachments (fragments write storage resources only)
/// and sets the viewport and scissor to it.
void beginRendering(VkCommandBuffer cmd, VkExtent2D extent);
inline void endRendering(VkCommandBuffer cmd) {
    vkCmdEndRendering(cmd);
}

} // namespace stsv
