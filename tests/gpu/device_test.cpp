#include "gpu/buffer.h"
#include "gpu/check.h"
#include "gpu/commands.h"
#include "gpu/device.h"
#include "gpu_fixture.h"

#include <gtest/gtest.h>

#include <cstdlib>

namespace stsv::test {
namespace {

TEST(ListDevices, FindsLavapipeWithGeometryShaders) {
    const std::vector<DeviceInfo> devices = listDevices();
    ASSERT_FALSE(devices.empty());
    bool found = false;
    for (const DeviceInfo& info : devices) {
        std::cout << describe(info);
        if (info.driverName != "llvmpipe") continue;
        found = true;
        EXPECT_EQ(info.type, VK_PHYSICAL_DEVICE_TYPE_CPU);
        EXPECT_TRUE(info.vulkan13) << apiVersionString(info.apiVersion);
        EXPECT_TRUE(info.geometryShader);
        EXPECT_TRUE(info.logicOp);
        EXPECT_TRUE(info.depthClamp);
        EXPECT_TRUE(info.fragmentStoresAndAtomics);
        EXPECT_TRUE(info.timestamps);
        EXPECT_GT(info.timestampPeriod, 0.0f);
        EXPECT_NE(describe(info).find("mesh shader (VK_EXT_mesh_shader)"), std::string::npos);
    }
    EXPECT_TRUE(found) << "lavapipe (driver llvmpipe) not among the Vulkan devices";
}

TEST(ListDevices, DescribeNamesEveryCapability) {
    DeviceInfo info;
    info.name = "Test GPU";
    info.apiVersion = VK_MAKE_API_VERSION(0, 1, 3, 250);
    info.geometryShader = true;
    info.meshShader = false;
    const std::string text = describe(info);
    EXPECT_NE(text.find("Test GPU"), std::string::npos) << text;
    EXPECT_NE(text.find("1.3.250"), std::string::npos) << text;
    EXPECT_NE(text.find("geometry shader: yes"), std::string::npos) << text;
    EXPECT_NE(text.find("mesh shader (VK_EXT_mesh_shader): no"), std::string::npos) << text;
}

TEST(VulkanError, CarriesResultExpressionAndPlace) {
    try {
        STSV_VK_CHECK(VK_ERROR_OUT_OF_DEVICE_MEMORY);
        FAIL() << "no throw";
    } catch (const VulkanError& e) {
        const std::string what = e.what();
        EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_DEVICE_MEMORY);
        EXPECT_NE(what.find("VK_ERROR_OUT_OF_DEVICE_MEMORY"), std::string::npos) << what;
        EXPECT_NE(what.find("device_test.cpp:"), std::string::npos) << what;
        EXPECT_EQ(e.expression(), "VK_ERROR_OUT_OF_DEVICE_MEMORY");
    }
    EXPECT_NO_THROW(STSV_VK_CHECK(VK_SUCCESS));
    EXPECT_EQ(toString(VkResult(-12345)), "VkResult(-12345)");
}

using DeviceTest = GpuTest;

TEST_F(DeviceTest, SharedDeviceIsValidatedLavapipeOrBetter) {
    EXPECT_TRUE(device().validationEnabled());
    EXPECT_TRUE(device().info().vulkan13);
    EXPECT_NE(device().handle(), VK_NULL_HANDLE);
    EXPECT_NE(device().queue(), VK_NULL_HANDLE);
    EXPECT_EQ(device().cmdDrawMeshTasks() != nullptr, device().info().meshShader);
}

TEST_F(DeviceTest, ValidationRecordsInvalidUsage) {
    // A buffer with no usage flags violates VUID-VkBufferCreateInfo-usage-requiredbitmask;
    // the layer must report it, or the zero-message checks of every other test prove nothing.
    VkBufferCreateInfo info{};
    info.sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO;
    info.size = 64;
    info.usage = 0;
    VkBuffer buffer = VK_NULL_HANDLE;
    const VkResult result = vkCreateBuffer(device().handle(), &info, nullptr, &buffer);
    if (result == VK_SUCCESS) vkDestroyBuffer(device().handle(), buffer, nullptr);
    const std::vector<ValidationMessage> messages = device().validationMessages();
    ASSERT_GE(messages.size(), 1u);
    bool named = false;
    for (const ValidationMessage& m : messages) named |= m.text.find("usage") != std::string::npos;
    EXPECT_TRUE(named) << formatMessages(messages);
    EXPECT_EQ(device().validationMessageCount(), messages.size());
    device().clearValidationMessages();
    EXPECT_EQ(device().validationMessageCount(), 0u);
}

TEST_F(DeviceTest, SynchronizationValidationReportsMissingBarrier) {
    // Fill then copy from the same buffer with no barrier in between: a read-after-write
    // hazard only synchronisation validation sees. Proves the tests' device checks barriers.
    Buffer a(device(), 256, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, MemoryUsage::DeviceLocal);
    Buffer b(device(), 256, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryUsage::DeviceLocal);
    submitOnce(device(), [&](VkCommandBuffer cmd) {
        vkCmdFillBuffer(cmd, a.handle(), 0, 256, 1u);
        const VkBufferCopy region{0, 0, 256};
        vkCmdCopyBuffer(cmd, a.handle(), b.handle(), 1, &region);
    });
    const std::vector<ValidationMessage> messages = device().validationMessages();
    ASSERT_GE(messages.size(), 1u);
    EXPECT_NE(messages[0].text.find("SYNC-HAZARD-READ-AFTER-WRITE"), std::string::npos)
        << formatMessages(messages);
    device().clearValidationMessages();
}

TEST_F(DeviceTest, FindsHostVisibleAndDeviceLocalMemory) {
    const uint32_t host = device().findMemoryType(~0u, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
    EXPECT_TRUE(device().memoryTypeFlags(host) & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT);
    const uint32_t local = device().findMemoryType(~0u, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    EXPECT_TRUE(device().memoryTypeFlags(local) & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    EXPECT_THROW(device().findMemoryType(0u, VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT), Error);
}

TEST(DeviceSelection, ByNameSubstringAndIndexAndRejectsUnknown) {
    const std::vector<DeviceInfo> devices = listDevices();
    ASSERT_FALSE(devices.empty());
    std::size_t lavapipe = devices.size();
    for (std::size_t i = 0; i < devices.size(); ++i)
        if (devices[i].driverName == "llvmpipe") lavapipe = i;
    ASSERT_LT(lavapipe, devices.size());
    {
        // Case-insensitive substring of "llvmpipe (LLVM 15.0.6, 256 bits)".
        Device byName(deviceOptions("LLVMpipe", true));
        EXPECT_EQ(byName.info().name, devices[lavapipe].name);
        EXPECT_EQ(byName.validationMessageCount(), 0u) << formatMessages(byName.validationMessages());
    }
    {
        Device byIndex(deviceOptions(std::to_string(lavapipe), false));
        EXPECT_EQ(byIndex.info().index, lavapipe);
    }
    EXPECT_THROW(Device(deviceOptions("no-such-gpu-xyz", false)), UsageError);
    EXPECT_THROW(Device(deviceOptions("99", false)), UsageError);
    EXPECT_THROW(Device(deviceOptions("123456789012345678901234567890", false)), UsageError);
    try {
        Device bad(deviceOptions("no-such-gpu-xyz", false));
    } catch (const UsageError& e) {
        EXPECT_NE(std::string(e.what()).find(devices[lavapipe].name), std::string::npos)
            << "the error should list the available devices: " << e.what();
    }
}

TEST(DeviceLifetime, CreateUseDestroyWithoutValidationMessages) {
    // Holding the log past the device also catches messages from vkDestroyDevice (leaks).
    std::shared_ptr<ValidationLog> log;
    {
        Device device(deviceOptions("", true));
        log = device.validationLog();
        ASSERT_NE(log, nullptr);
        Buffer buffer(device, 256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryUsage::DeviceLocal);
        const std::vector<uint32_t> values(64, 7u);
        buffer.upload(std::span<const uint32_t>(values));
        EXPECT_EQ(buffer.download<uint32_t>(), values);
    }
    EXPECT_EQ(log->count(), 0u) << formatMessages(log->messages());
}

TEST(DeviceValidation, EnvironmentVariableForcesValidation) {
    const char* old = std::getenv("STSV_VALIDATION");
    const std::string saved = old != nullptr ? old : "";
    setenv("STSV_VALIDATION", "1", 1);
    {
        Device device(deviceOptions("", false));
        EXPECT_TRUE(device.validationEnabled());
    }
    setenv("STSV_VALIDATION", "0", 1);
    {
        Device device(deviceOptions("", false));
        EXPECT_FALSE(device.validationEnabled());
        EXPECT_EQ(device.validationLog(), nullptr);
    }
    if (old != nullptr)
        setenv("STSV_VALIDATION", saved.c_str(), 1);
    else
        unsetenv("STSV_VALIDATION");
}

} // namespace
} // namespace stsv::test
