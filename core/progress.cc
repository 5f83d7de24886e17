#include "core/progress.h"

#include <unistd.h>

#include <cstdio>
#include <mutex>

#include "core/stderr_capture.h"

namespace slamcmp {

Progress::Progress(std::string label, int total)
    : label_(std::move(label)), total_(total), enabled_(isatty(fileno(stderr)) != 0) {
  start_ = last_ = std::chrono::steady_clock::now();
}

Progress::~Progress() { finish(); }

void Progress::update(int done, const std::string& detail) {
  if (!enabled_ || finished_) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - last_ < std::chrono::milliseconds(100) && done != total_) return;  // ~10 redraws/s
  last_ = now;
  const double seconds = std::chrono::duration<double>(now - start_).count();
  const std::lock_guard<std::mutex> lock(stderrMutex());  // not into an image decoder's capture
  if (total_ > 0) {
    const int width = 30;
    const int filled = static_cast<int>(width * static_cast<double>(done) / total_);
    std::fprintf(stderr, "\r%s [%-*s] %d/%d %.1fs %s\033[K", label_.c_str(), width,
                 std::string(filled, '#').c_str(), done, total_, seconds, detail.c_str());
  } else {
    std::fprintf(stderr, "\r%s %d %.1fs %s\033[K", label_.c_str(), done, seconds, detail.c_str());
  }
  std::fflush(stderr);
}

void Progress::finish() {
  if (!enabled_ || finished_) return;
  finished_ = true;
  const std::lock_guard<std::mutex> lock(stderrMutex());
  std::fprintf(stderr, "\n");
}

}  // namespace slamcmp
