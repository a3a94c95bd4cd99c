#include "core/progress.h"

#include <cstdio>
#include <unistd.h>

namespace stsv {

namespace {
std::atomic<int> g_enabled{-1}; // -1: decide by isatty(stderr)
}

void Progress::setEnabled(bool enabled) {
    g_enabled = enabled ? 1 : 0;
}

Progress::Progress(std::string label, std::size_t total)
    : m_label(std::move(label)), m_total(total), m_start(std::chrono::steady_clock::now()),
      m_lastDraw(m_start) {
    const int e = g_enabled.load();
    m_active = e == 1 || (e == -1 && isatty(fileno(stderr)));
}

Progress::~Progress() {
    finish();
}

void Progress::advance(std::size_t amount) {
    const std::size_t done = m_done.fetch_add(amount) + amount;
    if (!m_active) return;
    const auto now = std::chrono::steady_clock::now();
    std::unique_lock lock(m_mutex, std::try_to_lock);
    if (!lock.owns_lock() || now - m_lastDraw < std::chrono::milliseconds(100)) return;
    m_lastDraw = now;
    draw(done);
}

void Progress::draw(std::size_t done) {
    const double fraction = m_total ? double(done) / double(m_total) : 1.0;
    const int width = 30;
    const int filled = static_cast<int>(fraction * width);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
    std::fprintf(stderr, "\r%-20s [%.*s%*s] %5.1f%% %6.1fs", m_label.c_str(), filled,
                 "##############################", width - filled, "", 100.0 * fraction, seconds);
    std::fflush(stderr);
}

void Progress::finish() {
    if (!m_active || m_finished) return;
    m_finished = true;
    std::lock_guard lock(m_mutex);
    draw(m_total);
    std::fputc('\n', stderr);
}

} // namespace stsv
