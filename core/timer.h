#pragma once

#include <chrono>

namespace stsv {

/// Wall-clock stopwatch in milliseconds.
class Timer {
  public:
    Timer() : m_start(std::chrono::steady_clock::now()) {}
    double milliseconds() const {
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - m_start).count();
    }
    void reset() { m_start = std::chrono::steady_clock::now(); }

  private:
    std::chrono::steady_clock::time_point m_start;
};

} // namespace stsv
