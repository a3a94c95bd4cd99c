#include "gpu/device.h"

#include "gpu/check.h"

#include "core/files.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>

namespace stsv {
namespace {

constexpr const char* VALIDATION_LAYER = "VK_LAYER_KHRONOS_validation";

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

/// What a user without a Vulkan driver reads, and can act on.
constexpr const char* NO_DRIVER =
    "no Vulkan driver was found: install one (on Debian: apt install mesa-vulkan-drivers for lavapipe, "
    "the CPU driver; or your GPU vendor's driver), or render without Vulkan with --backend cpu";

/// The variable that points the Vulkan loader at driver manifests instead of the system's
/// (VK_DRIVER_FILES, or the older VK_ICD_FILENAMES it replaces) and its value; empty when neither
/// is set.
struct DriverFiles {
    std::string variable;
    std::string value;
};

DriverFiles driverFiles() {
    for (const char* name : {"VK_DRIVER_FILES", "VK_ICD_FILENAMES"})
        if (const char* value = std::getenv(name); value != nullptr && *value != '\0') return {name, value};
    return {};
}

/// What is wrong with the driver manifest `path` that the loader would trip over, or empty: it
/// must be a JSON object with a "file_format_version" string and an "ICD" object whose
/// "library_path" names a library (a path, relative to the manifest's folder, that exists; a bare
/// name is the dynamic linker's to find).
std::string manifestProblem(const std::string& path) {
    std::string text;
    try {
        text = readFileBytes(path, "driver manifest", std::size_t(1) << 20);
    } catch (const InputError&) {
        const std::string reason = notAFileReason(path);
        return reason.empty() ? "cannot be read" : reason;
    }
    nlohmann::json manifest;
    try {
        manifest = nlohmann::json::parse(text);
    } catch (const nlohmann::json::parse_error& e) {
        return "is not valid JSON (a syntax error at byte " + std::to_string(e.byte) + ")";
    }
    if (!manifest.is_object()) return "is not a JSON object";
    if (!manifest.contains("file_format_version") || !manifest["file_format_version"].is_string())
        return "lacks \"file_format_version\" (a string such as \"1.0.0\")";
    if (!manifest.contains("ICD") || !manifest["ICD"].is_object())
        return "lacks the \"ICD\" object (an ICD manifest has \"ICD\": {\"library_path\": ...})";
    const nlohmann::json& icd = manifest["ICD"];
    if (!icd.contains("library_path") || !icd["library_path"].is_string() ||
        icd["library_path"].get<std::string>().empty())
        return "lacks \"ICD\".\"library_path\", the driver library to load";
    const std::filesystem::path library = icd["library_path"].get<std::string>();
    if (library.has_parent_path()) {
        const std::filesystem::path resolved =
            (library.is_absolute() ? library : std::filesystem::path(path).parent_path() / library)
                .lexically_normal();
        if (const std::string reason = notAFileReason(resolved.string()); !reason.empty())
            return "names the driver library " + resolved.string() + ", which " + reason;
    }
    return {};
}

/// When the loader reads the drivers of VK_DRIVER_FILES (or VK_ICD_FILENAMES) and one of the
/// manifests named there has a problem: the first, as "<variable> names <what>, which <problem>".
/// `missing` tells whether it is only that the file does not exist. Empty otherwise.
std::string driverFilesProblem(bool& missing) {
    const DriverFiles files = driverFiles();
    missing = false;
    std::size_t start = 0;
    while (!files.value.empty() && start <= files.value.size()) {
        const std::size_t end = std::min(files.value.find(':', start), files.value.size());
        const std::string entry = files.value.substr(start, end - start);
        start = end + 1;
        if (entry.empty()) continue;
        // An entry is a manifest, or a folder of them (its .json files).
        std::vector<std::string> manifests;
        std::error_code ec;
        if (std::filesystem::is_directory(entry, ec)) {
            for (const auto& e : std::filesystem::directory_iterator(entry, ec))
                if (e.path().extension() == ".json") manifests.push_back(e.path().string());
            std::sort(manifests.begin(), manifests.end());
            if (manifests.empty())
                return files.variable + " names the folder " + entry +
                       ", which holds no driver manifest (.json)";
        } else {
            manifests.push_back(entry);
        }
        for (const std::string& manifest : manifests)
            if (const std::string problem = manifestProblem(manifest); !problem.empty()) {
                missing = problem == "does not exist";
                return files.variable + " names the Vulkan driver manifest " + manifest + ", which " +
                       problem;
            }
    }
    return {};
}

/// The message of a failed loader call (vkCreateInstance, vkEnumeratePhysicalDevices) where
/// VK_DRIVER_FILES or VK_ICD_FILENAMES chose the drivers: what is wrong with the manifests they
/// name, or that the loader read only those. Empty when neither is set.
std::string driverFilesMessage(const char* call, VkResult result) {
    const DriverFiles files = driverFiles();
    if (files.variable.empty()) return {};
    const std::string failed = std::string(call) + ": " + toString(result);
    bool missing = false;
    const std::string problem = driverFilesProblem(missing);
    if (missing) return std::string(NO_DRIVER) + " (" + problem + "; " + failed + ")";
    if (!problem.empty())
        return problem + ": fix it or unset " + files.variable +
               " (the loader then reads the system's drivers), or render without Vulkan with --backend cpu "
               "(" +
               failed + ")";
    return failed + " with " + files.variable + "=" + files.value +
           " (the loader reads only the drivers those manifests name): check them or unset " +
           files.variable + ", or render without Vulkan with --backend cpu";
}

/// Refuses, before the loader reads them, the entries of the variables that point it at driver
/// and layer manifests which are neither a regular file nor a folder: the loader fopen()s each
/// entry, and each .json in a folder entry, and a FIFO without a writer blocks that open for ever
/// (a device or socket is no manifest either). Error naming the variable and the entry.
void checkManifestVariables() {
    constexpr const char* kNotAManifest = "is a device, pipe or socket, not a regular file";
    for (const char* name : {"VK_DRIVER_FILES", "VK_ICD_FILENAMES", "VK_ADD_DRIVER_FILES", "VK_LAYER_PATH",
                             "VK_ADD_LAYER_PATH"}) {
        const char* value = std::getenv(name);
        if (value == nullptr) continue;
        const std::string list = value;
        auto refuse = [&](const std::string& entry, const std::string& what) {
            throw Error(std::string(name) + " names " + what + entry + ", which " + kNotAManifest +
                        ": the Vulkan loader would wait on it for ever; name manifests (.json) or folders "
                        "of them, or unset " +
                        name + ", or render without Vulkan with --backend cpu");
        };
        for (std::size_t start = 0; start <= list.size();) {
            const std::size_t end = std::min(list.find(':', start), list.size());
            const std::string entry = list.substr(start, end - start);
            start = end + 1;
            if (entry.empty()) continue;
            std::error_code ec;
            const std::filesystem::file_status status = std::filesystem::status(entry, ec);
            if (ec || !std::filesystem::exists(status)) continue; // the loader skips it
            if (std::filesystem::is_directory(status)) {
                for (const auto& e : std::filesystem::directory_iterator(entry, ec))
                    if (e.path().extension() == ".json" && !e.is_regular_file(ec) && !e.is_directory(ec) &&
                        e.exists(ec))
                        refuse(e.path().string(), "the folder " + entry + " holding ");
            } else if (!std::filesystem::is_regular_file(status)) {
                refuse(entry, "");
            }
        }
    }
}

/// A Vulkan 1.3 instance without surface extensions; `log` non-null enables validation.
VkInstance createInstance(ValidationLog* log, bool synchronizationValidation) {
    checkManifestVariables();
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
    const char* layers[] = {VALIDATION_LAYER};
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
        if (!hasLayer(VALIDATION_LAYER))
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
    // A manifest of VK_DRIVER_FILES the loader could not use fails here, as "no driver" or, for
    // text that is not a manifest, as VK_ERROR_OUT_OF_HOST_MEMORY: the manifest is named instead.
    if (result != VK_SUCCESS)
        if (const std::string message = driverFilesMessage("vkCreateInstance", result); !message.empty())
            throw Error(message);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw Error(std::string(NO_DRIVER) + " (vkCreateInstance: VK_ERROR_INCOMPATIBLE_DRIVER)");
    STSV_VK_CHECK(result);
    return instance;
}

std::vector<VkPhysicalDevice> physicalDevices(VkInstance instance) {
    uint32_t count = 0;
    if (const VkResult result = vkEnumeratePhysicalDevices(instance, &count, nullptr); result != VK_SUCCESS)
        if (const std::string message = driverFilesMessage("vkEnumeratePhysicalDevices", result);
            !message.empty())
            throw Error(message);
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
        if (infos.empty()) {
            const DriverFiles files = driverFiles();
            throw Error(std::string(NO_DRIVER) + " (the Vulkan loader lists no device" +
                        (files.variable.empty()
                             ? std::string()
                             : " of the drivers " + files.variable + "=" + files.value + " names") +
                        ")");
        }
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
