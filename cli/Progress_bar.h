// A progress bar on stderr for long report runs: drawn only when stderr is a terminal, only once
// a run has lasted a second (short runs stay silent), redrawn at most ten times a second, and
// erased when the run ends so the terminal keeps only the summary.
#pragma once

#include <chrono>
#include <string>

namespace extremal::cli {

class Progress_bar {
 public:
  // `enabled` false (--quiet) or stderr not a terminal: the bar never draws.
  Progress_bar(bool enabled, std::string label, long total);
  ~Progress_bar();
  Progress_bar(const Progress_bar&) = delete;
  Progress_bar& operator=(const Progress_bar&) = delete;

  void update(long done);
  // Erases the bar if it was drawn.
  void finish();

  // What one redraw writes (without the leading carriage return), for tests.
  static std::string render(const std::string& label, long done, long total, double elapsed_s,
                            int width);

 private:
  using Clock = std::chrono::steady_clock;
  bool m_enabled;
  std::string m_label;
  long m_total;
  Clock::time_point m_start, m_last_draw;
  bool m_drawn = false;
  std::size_t m_drawn_width = 0;
};

}  // namespace extremal::cli
