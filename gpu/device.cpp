#include "gpu/device.h"

#include "gpu/check.h"

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>

namespace stsv {
namespace {

constexpr const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

bool envFlag(const char* name) {
    const char* value = std::getenv(name);
    return value != nullptr && *value != '\0' && std::strcmp(value, "0") != 0;
}

bool hasLayer(const char* name) {
    uint32_t count = 0;
    STSV_VK_CHECK(vkEnumerateInstanceLayerProperties(&count, nullptr));
    std::vector<VkLayerProperties> layers(count);
    STSV_VK_CHECK(vkEnumerateInstanceLayerProperties(&count, layers.data()));
    return std::any_of(layers.begin(), layers.end(),
                       [&](const VkLayerProperties& l) { return std::strcmp(l.layerName, name) == 0; });
}

bool hasDeviceExtension(VkPhysicalDevice physicalDevice, const char* name) {
    uint32_t count = 0;
    STSV_VK_CHECK(vkEnumerateDeviceExtensionProperties(physicalDevice, nullptr, &count, nullptr));
    std::vector<VkExtensionProperties> extensions(count);
    STSV_VK_CHECK(vkEnumerateDeviceExtensionProperties(physicalDevice, nullptr, &count, extensions.data()));
    return std::any_of(extensions.begin(), extensions.end(), [&](const VkExtensionProperties& e) {
        return std::strcmp(e.extensionName, name) == 0;
    });
}

VKAPI_ATTR VkBool32 VKAPI_CALL recordMessage(VkDebugUtilsMessageSeverityFlagBitsEXT severity,
                                             VkDebugUtilsMessageTypeFlagsEXT /*types*/,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
    auto* log = static_cast<ValidationLog*>(user);
    std::string text;
    if (data->pMessageIdName != nullptr) text = std::string("[") + data->pMessageIdName + "] ";
    if (data->pMessage != nullptr) text += data->pMessage;
    log->record({severity, std::move(text)});
    return VK_FALSE; // never abort the call
}

VkDebugUtilsMessengerCreateInfoEXT messengerInfo(ValidationLog* log) {
    VkDebugUtilsMessengerCreateInfoEXT info{};
    info.sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT;
    info.messageSeverity =
        VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
    info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
    info.pfnUserCallback = recordMessage;
    info.pUserData = log;
    return info;
}

/// A Vulkan 1.3 instance without surface extensions; `log` non-null enables validation.
/// What a user without a Vulkan driver reads, and can act on.
constexpr const char* kNoDriver =
    "no Vulkan driver was found: install one (on Debian: apt install mesa-vulkan-drivers for lavapipe, "
    "the CPU driver; or your GPU vendor's driver), or render without Vulkan with --backend cpu";

VkInstance createInstance(ValidationLog* log, bool synchronizationValidation) {
    loadVulkan();
    VkApplicationInfo app{};
    app.sType = VK_STRUCTURE_TYPE_APPLICATION_INFO;
    app.pApplicationName = "stsv";
    app.applicationVersion = VK_MAKE_API_VERSION(0, 0, 1, 0);
    app.pEngineName = "stsv";
    app.apiVersion = VK_API_VERSION_1_3;

    VkInstanceCreateInfo info{};

    info.sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO;
    info.pApplicationInfo = &app;
    const char* layers[] = {kValidationLayer};
    const char* extensions[] = {VK_EXT_DEBUG_UTILS_EXTENSION_NAME, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME};
    VkDebugUtilsMessengerCreateInfoEXT messenger{};
    // VkValidationFeaturesEXT needs VK_EXT_validation_features, which the layer provides.
    const VkValidationFeatureEnableEXT enables[] = {
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features{};
    features.sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT;
    features.enabledValidationFeatureCount = 1;
    features.pEnabledValidationFeatures = enables;
    if (log != nullptr) {
        if (!hasLayer(kValidationLayer))
            throw Error("validation requested but VK_LAYER_KHRONOS_validation is not installed "
                        "(Debian package vulkan-validationlayers)");
        info.enabledLayerCount = 1;
        info.ppEnabledLayerNames = layers;
        info.enabledExtensionCount = synchronizationValidation ? 2 : 1;
        info.ppEnabledExtensionNames = extensions;
        // Chained so instance creation and destruction are reported too.
        messenger = messengerInfo(log);
        info.pNext = &messenger;
        if (synchronizationValidation) messenger.pNext = &features;
    }
    VkInstance instance = VK_NULL_HANDLE;
    const VkResult result = vkCreateInstance(&info, nullptr, &instance);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw Error(std::string(kNoDriver) + " (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER)");
    STSV_VK_CHECK(result);
    return instance;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
    uint32_t count = 0;
    STSV_VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, nullptr));
    std::vector<VkPhysicalDevice> devices(count);
    STSV_VK_CHECK(vkEnumeratePhysicalDevices(instance, &count, devices.data()));
    return devices;
}

/// Index of the first queue family with graphics and compute, or UINT32_MAX.
uint32_t findQueueFamily(VkPhysicalDevice physicalDevice, uint32_t* timestampValidBits) {
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(physicalDevice, &count, nullptr);
    std::vector<VkQueueFamilyProperties> families(count);
    vkGetPhysicalDeviceQueueFamilyProperties(physicalDevice, &count, families.data());
    for (uint32_t i = 0; i < count; ++i) {
        const VkQueueFlags needed = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
        if ((families[i].queueFlags & needed) == needed) {
            if (timestampValidBits != nullptr) *timestampValidBits = families[i].timestampValidBits;
            return i;
        }
    }
    return UINT32_MAX;
}

/// Supported features of one physical device, in one pNext chain.
struct FeatureChain {
    VkPhysicalDeviceFeatures2 core{};
    VkPhysicalDeviceVulkan12Features v12{};
    VkPhysicalDeviceVulkan13Features v13{};
    VkPhysicalDeviceMeshShaderFeaturesEXT mesh{};

    /// Links the chain; the mesh struct only when the extension exists (a struct of an
    /// unsupported extension in the chain is invalid usage).
    void link(bool withMesh) {
        core.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2;
        v12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
        v13.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES;
        mesh.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_FEATURES_EXT;
        core.pNext = &v12;
        v12.pNext = &v13;
        v13.pNext = withMesh ? &mesh : nullptr;
        mesh.pNext = nullptr;
    }
};

DeviceInfo queryDeviceInfo(VkPhysicalDevice physicalDevice, uint32_t index) {
    VkPhysicalDeviceMaintenance3Properties maintenance3{};
    maintenance3.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MAINTENANCE_3_PROPERTIES;
    VkPhysicalDeviceDriverProperties driver{};
    driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
    driver.pNext = &maintenance3;
    const bool meshExtension = hasDeviceExtension(physicalDevice, VK_EXT_MESH_SHADER_EXTENSION_NAME);
    VkPhysicalDeviceMeshShaderPropertiesEXT mesh{};
    mesh.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_MESH_SHADER_PROPERTIES_EXT;
    maintenance3.pNext = meshExtension ? &mesh : nullptr;
    VkPhysicalDeviceProperties2 props{};
    props.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2;
    props.pNext = &driver;
    vkGetPhysicalDeviceProperties2(physicalDevice, &props);

    FeatureChain features;
    features.link(meshExtension);
    vkGetPhysicalDeviceFeatures2(physicalDevice, &features.core);

    uint32_t validBits = 0;
    const uint32_t family = findQueueFamily(physicalDevice, &validBits);

    DeviceInfo info;
    info.index = index;
    info.name = props.properties.deviceName;
    info.driverName = driver.driverName;
    info.driverInfo = driver.driverInfo;
    info.apiVersion = props.properties.apiVersion;
    info.type = props.properties.deviceType;
    info.vulkan13 = VK_API_VERSION_MAJOR(info.apiVersion) == 1 &&
                    VK_API_VERSION_MINOR(info.apiVersion) >= 3 && features.v13.dynamicRendering &&
                    features.v13.synchronization2 && family != UINT32_MAX;
    info.geometryShader = features.core.features.geometryShader;
    info.meshShader = meshExtension && features.mesh.meshShader;
    info.taskShader = meshExtension && features.mesh.taskShader;
    if (info.meshShader) {
        info.maxMeshOutputVertices = mesh.maxMeshOutputVertices;
        info.maxMeshOutputPrimitives = mesh.maxMeshOutputPrimitives;
        info.maxMeshOutputMemorySize = mesh.maxMeshOutputMemorySize;
        info.maxMeshSharedMemorySize = mesh.maxMeshSharedMemorySize;
        info.maxTaskWorkGroupCountX = mesh.maxTaskWorkGroupCount[0];
    }
    info.logicOp = features.core.features.logicOp;
    info.fragmentStoresAndAtomics = features.core.features.fragmentStoresAndAtomics;
    info.vertexPipelineStoresAndAtomics = features.core.features.vertexPipelineStoresAndAtomics;
    info.depthClamp = features.core.features.depthClamp;
    info.shaderInt64 = features.core.features.shaderInt64;
    info.bufferDeviceAddress = features.v12.bufferDeviceAddress;
    info.maxMemoryAllocationSize = maintenance3.maxMemoryAllocationSize;
    info.timestamps = props.properties.limits.timestampComputeAndGraphics && validBits > 0;
    info.timestampPeriod = props.properties.limits.timestampPeriod;
    info.maxImageDimension2D = props.properties.limits.maxImageDimension2D;
    info.maxColorAttachments = props.properties.limits.maxColorAttachments;
    info.maxGeometryOutputVertices = props.properties.limits.maxGeometryOutputVertices;

    VkPhysicalDeviceMemoryProperties memory;
    vkGetPhysicalDeviceMemoryProperties(physicalDevice, &memory);
    for (uint32_t i = 0; i < memory.memoryHeapCount; ++i)
        if (memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            info.deviceLocalBytes = std::max<uint64_t>(info.deviceLocalBytes, memory.memoryHeaps[i].size);
    return info;
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

/// Implements DeviceOptions::select over `infos`; returns an index into `infos`.
std::size_t selectDevice(const std::vector<DeviceInfo>& infos, const std::string& select) {
    auto usable = [](const DeviceInfo& i) { return i.vulkan13; };
    auto names = [&] {
        std::string list;
        for (const DeviceInfo& i : infos)
            list += (list.empty() ? "" : ", ") + std::to_string(i.index) + ": " + i.name;
        return list.empty() ? std::string("none") : list;
    };
    std::size_t chosen = infos.size();
    if (select.empty()) {
        for (VkPhysicalDeviceType type :
             {VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU, VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU,
              VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU, VK_PHYSICAL_DEVICE_TYPE_CPU,
              VK_PHYSICAL_DEVICE_TYPE_OTHER}) {
            for (std::size_t i = 0; i < infos.size() && chosen == infos.size(); ++i)
                if (infos[i].type == type && usable(infos[i])) chosen = i;
        }
        if (infos.empty()) throw Error(std::string(kNoDriver) + " (the Vulkan loader lists no device)");
        if (chosen == infos.size())
            throw Error("no Vulkan 1.3 device with dynamic rendering and synchronization2 (devices: " +
                        names() + ")");
        return chosen;
    }
    if (std::all_of(select.begin(), select.end(), [](unsigned char c) { return std::isdigit(c); })) {
        const unsigned long index = select.size() > 9 ? ULONG_MAX : std::stoul(select);
        if (index >= infos.size())
            throw UsageError("device index " + select + " out of range (devices: " + names() + ")");
        chosen = index;
    } else {
        for (std::size_t i = 0; i < infos.size() && chosen == infos.size(); ++i)
            if (lower(infos[i].name).find(lower(select)) != std::string::npos) chosen = i;
        if (chosen == infos.size())
            throw UsageError("no Vulkan device name contains '" + select + "' (devices: " + names() + ")");
    }
    if (!usable(infos[chosen]))
        throw UsageError("device '" + infos[chosen].name +
                         "' lacks Vulkan 1.3 with dynamic rendering and synchronization2");
    return chosen;
}

} // namespace

std::string apiVersionString(uint32_t apiVersion) {
    return std::to_string(VK_API_VERSION_MAJOR(apiVersion)) + "." +
           std::to_string(VK_API_VERSION_MINOR(apiVersion)) + "." +
           std::to_string(VK_API_VERSION_PATCH(apiVersion));
}

const char* toString(VkPhysicalDeviceType type) {
    switch (type) {
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
        return "integrated-gpu";
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
        return "discrete-gpu";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
        return "virtual-gpu";
    case VK_PHYSICAL_DEVICE_TYPE_CPU:
        return "cpu";
    default:
        return "other";
    }
}

std::string describe(const DeviceInfo& info) {
    auto yesNo = [](bool b) { return b ? "yes" : "no"; };
    std::ostringstream out;
    out << "device " << info.index << ": " << info.name << "\n"
        << "  type: " << toString(info.type) << "\n"
        << "  driver: " << info.driverName << " (" << info.driverInfo << ")\n"
        << "  api: " << apiVersionString(info.apiVersion) << (info.vulkan13 ? "" : " (unusable: needs 1.3)")
        << "\n"
        << "  geometry shader: " << yesNo(info.geometryShader) << "\n"
        << "  mesh shader (VK_EXT_mesh_shader): " << yesNo(info.meshShader)
        << (info.meshShader ? (info.taskShader ? ", with task shader" : ", no task shader") : "") << "\n"
        << "  logic op: " << yesNo(info.logicOp) << ", depth clamp: " << yesNo(info.depthClamp)
        << ", fragment stores and atomics: " << yesNo(info.fragmentStoresAndAtomics) << "\n"
        << "  timestamps: " << yesNo(info.timestamps) << " (" << info.timestampPeriod << " ns/tick)\n"
        << "  device-local memory: " << (info.deviceLocalBytes >> 20) << " MiB, max 2D image "
        << info.maxImageDimension2D << ", max color attachments " << info.maxColorAttachments << "\n";
    return out.str();
}

std::vector<DeviceInfo> listDevices() {
    VkInstance instance = createInstance(nullptr, false);
    std::vector<DeviceInfo> infos;
    try {
        const std::vector<VkPhysicalDevice> devices = physicalDevices(instance);
        for (uint32_t i = 0; i < devices.size(); ++i) infos.push_back(queryDeviceInfo(devices[i], i));
    } catch (...) {
        vkDestroyInstance(instance, nullptr);
        throw;
    }
    vkDestroyInstance(instance, nullptr);
    return infos;
}

void ValidationLog::record(ValidationMessage message) {
    if (print) std::fprintf(stderr, "vulkan validation: %s\n", message.text.c_str());
    std::lock_guard lock(m_mutex);
    m_messages.push_back(std::move(message));
}

std::vector<ValidationMessage> ValidationLog::messages() const {
    std::lock_guard lock(m_mutex);
    return m_messages;
}

std::size_t ValidationLog::count() const {
    std::lock_guard lock(m_mutex);
    return m_messages.size();
}

void ValidationLog::clear() {
    std::lock_guard lock(m_mutex);
    m_messages.clear();
}

Device::Device(const DeviceOptions& options) {
    const char* env = std::getenv("STSV_VALIDATION");
    const bool envSync = env != nullptr && std::strcmp(env, "sync") == 0;
    if (options.validation || envFlag("STSV_VALIDATION")) {
        m_validationLog = std::make_shared<ValidationLog>();
        m_validationLog->print = options.printValidation;
    }
    try {
        m_instance = createInstance(m_validationLog.get(), options.synchronizationValidation || envSync);
        if (m_validationLog) {
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(m_instance, "vkCreateDebugUtilsMessengerEXT"));
            if (create == nullptr)
                throw Error("VK_EXT_debug_utils is missing although validation is enabled");
            const VkDebugUtilsMessengerCreateInfoEXT info = messengerInfo(m_validationLog.get());
            STSV_VK_CHECK(create(m_instance, &info, nullptr, &m_messenger));
        }

        const std::vector<VkPhysicalDevice> devices = physicalDevices(m_instance);
        std::vector<DeviceInfo> infos;
        for (uint32_t i = 0; i < devices.size(); ++i) infos.push_back(queryDeviceInfo(devices[i], i));
        const std::size_t chosen = selectDevice(infos, options.select);
        m_physicalDevice = devices[chosen];
        m_info = infos[chosen];
        m_queueFamily = findQueueFamily(m_physicalDevice, nullptr);

        VkPhysicalDeviceProperties props;
        vkGetPhysicalDeviceProperties(m_physicalDevice, &props);
        m_limits = props.limits;
        vkGetPhysicalDeviceMemoryProperties(m_physicalDevice, &m_memory);

        // Enable what later passes use, where supported (DeviceInfo says which).
        FeatureChain supported;
        supported.link(m_info.meshShader);
        vkGetPhysicalDeviceFeatures2(m_physicalDevice, &supported.core);
        FeatureChain enabled;
        enabled.link(m_info.meshShader);
        VkPhysicalDeviceFeatures& core = enabled.core.features;
        const VkPhysicalDeviceFeatures& has = supported.core.features;
        core.geometryShader = has.geometryShader;
        core.logicOp = has.logicOp;
        core.depthClamp = has.depthClamp;
        core.fragmentStoresAndAtomics = has.fragmentStoresAndAtomics;
        core.vertexPipelineStoresAndAtomics = has.vertexPipelineStoresAndAtomics;
        core.independentBlend = has.independentBlend;
        core.shaderInt64 = has.shaderInt64;
        core.samplerAnisotropy = VK_FALSE;
        enabled.v12.hostQueryReset = supported.v12.hostQueryReset;
        enabled.v12.bufferDeviceAddress = supported.v12.bufferDeviceAddress;
        enabled.v12.scalarBlockLayout = supported.v12.scalarBlockLayout;
        enabled.v12.storageBuffer8BitAccess = supported.v12.storageBuffer8BitAccess;
        enabled.v12.shaderInt8 = supported.v12.shaderInt8;
        enabled.v13.dynamicRendering = VK_TRUE;
        enabled.v13.synchronization2 = VK_TRUE;
        enabled.v13.maintenance4 = supported.v13.maintenance4;
        enabled.mesh.meshShader = supported.mesh.meshShader;
        enabled.mesh.taskShader = supported.mesh.taskShader;

        const float priority = 1.0f;
        VkDeviceQueueCreateInfo queueInfo{};
        queueInfo.sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO;
        queueInfo.queueFamilyIndex = m_queueFamily;
        queueInfo.queueCount = 1;
        queueInfo.pQueuePriorities = &priority;

        std::vector<const char*> extensions;
        if (m_info.meshShader) extensions.push_back(VK_EXT_MESH_SHADER_EXTENSION_NAME);

        VkDeviceCreateInfo info{};

        info.sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO;
        info.pNext = &enabled.core;
        info.queueCreateInfoCount = 1;
        info.pQueueCreateInfos = &queueInfo;
        info.enabledExtensionCount = uint32_t(extensions.size());
        info.ppEnabledExtensionNames = extensions.data();
        STSV_VK_CHECK(vkCreateDevice(m_physicalDevice, &info, nullptr, &m_device));
        vkGetDeviceQueue(m_device, m_queueFamily, 0, &m_queue);
        if (m_info.meshShader)
            m_cmdDrawMeshTasks = reinterpret_cast<PFN_vkCmdDrawMeshTasksEXT>(
                vkGetDeviceProcAddr(m_device, "vkCmdDrawMeshTasksEXT"));
    } catch (...) {
        destroy();
        throw;
    }
}

Device::~Device() {
    destroy();
}

void Device::destroy() noexcept {
    if (m_device != VK_NULL_HANDLE) {
        vkDeviceWaitIdle(m_device);
        vkDestroyDevice(m_device, nullptr);
        m_device = VK_NULL_HANDLE;
    }
    if (m_messenger != VK_NULL_HANDLE) {
        auto destroyMessenger = reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
            vkGetInstanceProcAddr(m_instance, "vkDestroyDebugUtilsMessengerEXT"));
        if (destroyMessenger != nullptr) destroyMessenger(m_instance, m_messenger, nullptr);
        m_messenger = VK_NULL_HANDLE;
    }
    if (m_instance != VK_NULL_HANDLE) {
        vkDestroyInstance(m_instance, nullptr);
        m_instance = VK_NULL_HANDLE;
    }
}

std::vector<ValidationMessage> Device::validationMessages() const {
    return m_validationLog ? m_validationLog->messages() : std::vector<ValidationMessage>{};
}

std::size_t Device::validationMessageCount() const {
    return m_validationLog ? m_validationLog->count() : 0;
}

void Device::clearValidationMessages() {
    if (m_validationLog) m_validationLog->clear();
}

uint32_t Device::findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags required,
                                VkMemoryPropertyFlags preferred) const {
    uint32_t fallback = UINT32_MAX;
    for (uint32_t i = 0; i < m_memory.memoryTypeCount; ++i) {
        if (!(typeBits & (1u << i))) continue;
        const VkMemoryPropertyFlags flags = m_memory.memoryTypes[i].propertyFlags;
        if ((flags & required) != required) continue;
        if ((flags & preferred) == preferred) return i;
        if (fallback == UINT32_MAX) fallback = i;
    }
    if (fallback == UINT32_MAX)
        throw Error("no Vulkan memory type with property flags " + std::to_string(required) + " on " +
                    m_info.name);
    return fallback;
}

VkMemoryPropertyFlags Device::memoryTypeFlags(uint32_t typeIndex) const {
    return m_memory.memoryTypes[typeIndex].propertyFlags;
}

void Device::waitIdle() const {
    STSV_VK_CHECK(vkDeviceWaitIdle(m_device));
}

} // namespace stsv
