#include "tools/terminal_progress.h"

#include <unistd.h>

#include <cstdio>

namespace zbrdf {

TerminalProgress::TerminalProgress(bool quiet) : quiet_(quiet), is_tty_(isatty(2) != 0) {}

TerminalProgress::~TerminalProgress() {
  if (line_open_) std::fputc('\n', stderr);
}

ProgressCallback TerminalProgress::Callback() {
  return [this](const Progress& p) { Update(p); };
}

void TerminalProgress::Update(const Progress& p) {
  if (quiet_) return;
  const auto now = std::chrono::steady_clock::now();
  if (p.stage != stage_) {
    if (line_open_) std::fputc('\n', stderr);
    line_open_ = false;
    stage_ = p.stage;
    stage_start_ = now;
    last_draw_ = {};
  }
  const bool finished = p.total > 0 && p.done >= p.total;
  // Redraw at most 10 times a second on a terminal; in a log, every 10% and at the end.
  if (is_tty_) {
    if (!finished && now - last_draw_ < std::chrono::milliseconds(100)) return;
  } else if (!finished && p.total > 0) {
    const long step = std::max(1L, p.total / 10);
    if (p.done % step != 0) return;
  }
  last_draw_ = now;
  const double elapsed_s = std::chrono::duration<double>(now - stage_start_).count();
  char eta[32] = "";
  if (p.total > 0 && p.done > 0 && !finished) {
    std::snprintf(eta, sizeof(eta), ", ETA %.0f s", elapsed_s * (p.total - p.done) / p.done);
  }
  constexpr int kWidth = 30;
  const int filled = p.total > 0 ? static_cast<int>(kWidth * p.done / p.total) : 0;
  std::string bar(filled, '#');
  bar.resize(kWidth, '.');
  std::fprintf(stderr, "%s%-10s [%s] %ld/%ld %s, %.1f s%s%s", is_tty_ ? "\r" : "",
               p.stage.c_str(), bar.c_str(), p.done, p.total, p.unit.c_str(), elapsed_s, eta,
               is_tty_ ? "\033[K" : "\n");
  line_open_ = is_tty_;
  if (finished && is_tty_) {
    std::fputc('\n', stderr);
    line_open_ = false;
  }
  std::fflush(stderr);
}

}  // namespace zbrdf
