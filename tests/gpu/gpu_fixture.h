// Shared set-up of the GPU tests: one validated device and one shader compiler for the whole
// test binary; every test fails if the validation layer reported anything (DESIGN §5).
#pragma once

#include "gpu/device.h"
#include "gpu/shader_compiler.h"

#include <gtest/gtest.h>

#include <string>

namespace stsv::test {

inline DeviceOptions deviceOptions(std::string select, bool validation) {
    DeviceOptions options;
    options.select = std::move(select);
    options.validation = validation;
    options.synchronizationValidation = validation; // missing barriers fail the tests too
    return options;
}

/// The device every test shares: validation (with synchronisation validation) on, messages
/// recorded (not printed).
inline Device& sharedDevice() {
    static Device device(deviceOptions("", true));
    return device;
}

inline const ShaderCompiler& sharedCompiler() {
    static ShaderCompiler compiler;
    return compiler;
}

inline std::string formatMessages(const std::vector<ValidationMessage>& messages) {
    std::string text;
    for (const ValidationMessage& m : messages) text += "\n  " + m.text;
    return text;
}

/// Base fixture: asserts zero validation messages after each test.
class GpuTest : public ::testing::Test {
  protected:
    Device& device() { return sharedDevice(); }
    const ShaderCompiler& compiler() { return sharedCompiler(); }

    void SetUp() override {
        ASSERT_TRUE(device().validationEnabled());
        device().clearValidationMessages();
    }
    void TearDown() override {
        device().waitIdle();
        const std::vector<ValidationMessage> messages = device().validationMessages();
        EXPECT_EQ(messages.size(), 0u) << "validation messages:" << formatMessages(messages);
        device().clearValidationMessages();
    }
};

} // namespace stsv::test
