// Helpers for the scene tests: fixture files in a fresh temporary folder, error-message checks.
#pragma once

#include "core/error.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace stsv::test {

/// A fresh folder under the system temp dir, one per test (named after it), removed afterwards.
class TempDir {
  public:
    TempDir() {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_path = std::filesystem::temp_directory_path() /
                 ("stsv_scene_" + std::string(info->test_suite_name()) + "_" + info->name());
        std::filesystem::remove_all(m_path);
        std::filesystem::create_directories(m_path);
    }
    ~TempDir() {
        std::error_code ec;
        std::filesystem::remove_all(m_path, ec);
    }
    std::string write(const std::string& name, const std::string& text) const {
        std::string p = path(name);
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }
    std::string path(const std::string& name) const { return (m_path / name).string(); }

  private:
    std::filesystem::path m_path;
};

/// Runs `f`, expects exception type E whose message contains every one of `parts`.
template <class E> void expectError(const std::function<void()>& f, const std::vector<std::string>& parts) {
    try {
        f();
        ADD_FAILURE() << "expected an exception mentioning '" << (parts.empty() ? "" : parts[0]) << "'";
    } catch (const E& e) {
        const std::string what = e.what();
        for (const std::string& part : parts)
            EXPECT_NE(what.find(part), std::string::npos) << "message: " << what << "\nmissing: " << part;
        EXPECT_EQ(what.find('\n'), std::string::npos) << "message must be one line: " << what;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "wrong exception type, message: " << e.what();
    }
}

inline std::string dataPath(const std::string& name) {
    return std::string(STSV_TEST_DATA) + "/scene/" + name;
}

} // namespace stsv::test
