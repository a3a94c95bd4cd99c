// Headless Vulkan 1.3 instance and device (DESIGN §5): no surface, no window, no EGL.
// One graphics+compute queue; optional Khronos validation whose messages are recorded so
// tests can assert there were none.
#pragma once

#include "gpu/vulkan.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace stsv {

/// What `stsv info` prints about one physical device, and what passes test before choosing a
/// code path (geometry vs mesh shader extrusion).
struct DeviceInfo {
    uint32_t index = 0; ///< position in vkEnumeratePhysicalDevices order
    std::string name;
    std::string driverName;
    std::string driverInfo;
    uint32_t apiVersion = 0; ///< VK_MAKE_API_VERSION encoding
    VkPhysicalDeviceType type = VK_PHYSICAL_DEVICE_TYPE_OTHER;
    bool vulkan13 = false; ///< apiVersion ≥ 1.3 and dynamicRendering + synchronization2
    bool geometryShader = false;
    bool meshShader = false; ///< VK_EXT_mesh_shader present with its meshShader feature
    bool taskShader = false; ///< VK_EXT_mesh_shader's taskShader feature
    bool logicOp = false;
    bool fragmentStoresAndAtomics = false;
    bool vertexPipelineStoresAndAtomics = false;
    bool depthClamp = false;
    bool shaderInt64 = false;
    bool bufferDeviceAddress = false;     ///< Vulkan 1.2's bufferDeviceAddress feature
    uint64_t maxMemoryAllocationSize = 0; ///< bytes one allocation may hold (Vulkan 1.1)
    bool timestamps = false;              ///< timestampComputeAndGraphics and the queue has valid bits
    float timestampPeriod = 0.f;          ///< nanoseconds per timestamp tick
    uint64_t deviceLocalBytes = 0;        ///< largest device-local heap, bytes
    uint32_t maxImageDimension2D = 0;
    uint32_t maxColorAttachments = 0;
    uint32_t maxGeometryOutputVertices = 0;
    /// VK_EXT_mesh_shader's limits (0 without it): what one mesh workgroup may emit and keep.
    uint32_t maxMeshOutputVertices = 0;
    uint32_t maxMeshOutputPrimitives = 0;
    uint32_t maxMeshOutputMemorySize = 0; ///< bytes
    uint32_t maxMeshSharedMemorySize = 0; ///< bytes
    uint32_t maxTaskWorkGroupCountX = 0;
};

/// "1.3.230"
std::string apiVersionString(uint32_t apiVersion);
/// "cpu", "discrete-gpu", ...
const char* toString(VkPhysicalDeviceType type);
/// Several lines, `key: value`, as `stsv info` prints them.
std::string describe(const DeviceInfo& info);

/// Every physical device of the (headless) instance. Throws VulkanError when there is no
/// Vulkan loader or driver.
std::vector<DeviceInfo> listDevices();

struct DeviceOptions {
    /// Empty: the first discrete GPU, else integrated, else any (lavapipe). All digits: the
    /// index in listDevices(). Otherwise a case-insensitive substring of the device name.
    std::string select;
    /// VK_LAYER_KHRONOS_validation with a recording debug messenger. The environment variable
    /// STSV_VALIDATION=1 forces it on; STSV_VALIDATION=sync also turns on synchronizationValidation.
    bool validation = false;
    /// With validation: also the layer's synchronisation validation (hazards between commands
    /// missing a barrier). Slower; on in the GPU tests.
    bool synchronizationValidation = false;
    /// Echo each recorded validation message to stderr as it arrives.
    bool printValidation = false;
};

/// One warning or error from the validation layer (or the loader, through debug utils).
struct ValidationMessage {
    VkDebugUtilsMessageSeverityFlagBitsEXT severity;
    std::string text; ///< "[VUID-...] message"
};

/// Thread-safe store of validation messages (the messenger callback may run on any thread).
class ValidationLog {
  public:
    void record(ValidationMessage message);
    std::vector<ValidationMessage> messages() const;
    std::size_t count() const;
    void clear();
    bool print = false;

  private:
    mutable std::mutex m_mutex;
    std::vector<ValidationMessage> m_messages;
};

/// The Vulkan instance, the chosen physical device and its logical device with one queue.
/// Neither copyable nor movable: resources keep a pointer to it and must die first.
/// Queue submission is not synchronised: use one Device from one thread at a time.
class Device {
  public:
    explicit Device(const DeviceOptions& options = {});
    ~Device();
    Device(const Device&) = delete;
    Device& operator=(const Device&) = delete;

    VkInstance instance() const { return m_instance; }
    VkPhysicalDevice physicalDevice() const { return m_physicalDevice; }
    VkDevice handle() const { return m_device; }
    VkQueue queue() const { return m_queue; }
    uint32_t queueFamily() const { return m_queueFamily; }
    const DeviceInfo& info() const { return m_info; }
    const VkPhysicalDeviceLimits& limits() const { return m_limits; }

    bool validationEnabled() const { return m_validationLog != nullptr; }
    /// Warnings and errors recorded since the last clear (empty without validation).
    std::vector<ValidationMessage> validationMessages() const;
    std::size_t validationMessageCount() const;
    void clearValidationMessages();
    /// The log itself (null without validation); it outlives the Device for whoever holds it,
    /// so messages from vkDestroyDevice/vkDestroyInstance (leaks) can be checked too.
    std::shared_ptr<ValidationLog> validationLog() const { return m_validationLog; }

    /// Index of a memory type allowed by `typeBits` with all `required` flags, preferring one
    /// that also has `preferred`. Throws Error when none exists.
    uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                            VkMemoryPropertyFlags preferred = 0) const;
    VkMemoryPropertyFlags memoryTypeFlags(uint32_t typeIndex) const;

    /// vkCmdDrawMeshTasksEXT, or nullptr when the device lacks VK_EXT_mesh_shader.
    PFN_vkCmdDrawMeshTasksEXT cmdDrawMeshTasks() const { return m_cmdDrawMeshTasks; }

    void waitIdle() const;

  private:
    VkInstance m_instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT m_messenger = VK_NULL_HANDLE;
    VkPhysicalDevice m_physicalDevice = VK_NULL_HANDLE;
    VkDevice m_device = VK_NULL_HANDLE;
    VkQueue m_queue = VK_NULL_HANDLE;
    uint32_t m_queueFamily = 0;
    DeviceInfo m_info;
    VkPhysicalDeviceLimits m_limits{};
    VkPhysicalDeviceMemoryProperties m_memory{};
    std::shared_ptr<ValidationLog> m_validationLog;
    PFN_vkCmdDrawMeshTasksEXT m_cmdDrawMeshTasks = nullptr;

    void destroy() noexcept;
};

} // namespace stsv
