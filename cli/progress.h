// A terminal progress bar on stderr, drawn only when stderr is a terminal and at most
// ten times a second; safe to update from worker threads.
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>

namespace penumbra {

class ProgressBar {
 public:
  explicit ProgressBar(std::string label);
  ~ProgressBar();
  void update(double fraction);
  void finish();

 private:
  void draw(double fraction);
  std::string label_;
  bool enabled_;
  bool finished_ = false;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_, lastDraw_;
};

}  // namespace penumbra
