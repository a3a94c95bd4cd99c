// Progress display for long-running commands: a bar on a terminal, nothing otherwise.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace stsv {

class Progress {
  public:
    /// Shows `label` and a bar on stderr when stderr is a terminal (or when forced).
    Progress(std::string label, std::size_t total);
    ~Progress();
    Progress(const Progress&) = delete;
    Progress& operator=(const Progress&) = delete;

    /// Thread-safe; redraws at most ten times a second.
    void advance(std::size_t amount = 1);
    void finish();

    /// Turns the display off (or on) for the whole process, e.g. for --quiet or in tests.
    static void setEnabled(bool enabled);

  private:
    void draw(std::size_t done);

    std::string m_label;
    std::size_t m_total;
    std::atomic<std::size_t> m_done{0};
    std::mutex m_mutex;
    std::chrono::steady_clock::time_point m_start;
    std::chrono::steady_clock::time_point m_lastDraw;
    bool m_active;
    bool m_finished = false;
};

} // namespace stsv
