#include "cli/Progress_bar.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

namespace extremal::cli {

Progress_bar::Progress_bar(bool enabled, std::string label, long total)
    : m_enabled(enabled && ::isatty(STDERR_FILENO) == 1 && total > 0),
      m_label(std::move(label)),
      m_total(total),
      m_start(Clock::now()),
      m_last_draw(m_start) {}

Progress_bar::~Progress_bar() { finish(); }

std::string Progress_bar::render(const std::string& label, long done, long total,
                                 double elapsed_s, int width) {
  done = std::clamp(done, 0L, total);
  const double fraction = total > 0 ? static_cast<double>(done) / total : 1.0;
  const int filled = static_cast<int>(fraction * width);
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(static_cast<std::size_t>(width), '.');
  char tail[96];
  if (done > 0 && done < total) {
    const double remaining = elapsed_s * (total - done) / done;
    std::snprintf(tail, sizeof tail, " %3d%% %ld/%ld steps, %.0f s left",
                  static_cast<int>(100 * fraction), done, total, remaining + 0.5);
  } else {
    std::snprintf(tail, sizeof tail, " %3d%% %ld/%ld steps", static_cast<int>(100 * fraction),
                  done, total);
  }
  return label + " [" + bar + "]" + tail;
}

void Progress_bar::update(long done) {
  if (!m_enabled) return;
  const Clock::time_point now = Clock::now();
  const double elapsed = std::chrono::duration<double>(now - m_start).count();
  if (elapsed < 1.0) return;  // short runs: no bar
  if (m_drawn && now - m_last_draw < std::chrono::milliseconds(100)) return;
  m_last_draw = now;
  const std::string line = render(m_label, done, m_total, elapsed, 30);
  // Pad over a longer previous line.
  std::string padded = line;
  if (padded.size() < m_drawn_width) padded.resize(m_drawn_width, ' ');
  std::fprintf(stderr, "\r%s", padded.c_str());
  std::fflush(stderr);
  m_drawn = true;
  m_drawn_width = line.size();
}

void Progress_bar::finish() {
  if (!m_drawn) return;
  std::fprintf(stderr, "\r%s\r", std::string(m_drawn_width, ' ').c_str());
  std::fflush(stderr);
  m_drawn = false;
}

}  // namespace extremal::cli
