#include "cli/progress.h"

#include <unistd.h>

#include <cstdio>

namespace penumbra {

ProgressBar::ProgressBar(std::string label)
    : label_(std::move(label)),
      enabled_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()),
      lastDraw_(start_) {}

ProgressBar::~ProgressBar() { finish(); }

void ProgressBar::update(double fraction) {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto now = std::chrono::steady_clock::now();
  if (finished_ || now - lastDraw_ < std::chrono::milliseconds(100)) return;
  lastDraw_ = now;
  draw(fraction);
}

void ProgressBar::finish() {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (finished_) return;
  finished_ = true;
  draw(1.0);
  std::fputc('\n', stderr);
}

void ProgressBar::draw(double fraction) {
  constexpr int kWidth = 40;
  const int filled = int(fraction * kWidth + 0.5);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string bar(size_t(filled), '=');
  bar.resize(kWidth, ' ');
  std::fprintf(stderr, "\r%s [%s] %3d%% %.1fs", label_.c_str(), bar.c_str(),
               int(fraction * 100 + 0.5), seconds);
  std::fflush(stderr);
}

}  // namespace penumbra
