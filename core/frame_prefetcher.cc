#include "core/frame_prefetcher.h"

#include <chrono>

namespace slamcmp {

FramePrefetcher::FramePrefetcher(FrameSource& source, int max_frames, int depth)
    : source_(source), max_frames_(max_frames), depth_(static_cast<size_t>(std::max(1, depth))) {
  thread_ = std::thread([this] { run(); });
}

FramePrefetcher::~FramePrefetcher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  space_.notify_all();
  thread_.join();
}

void FramePrefetcher::run() {
  try {
    for (int n = 0; max_frames_ < 0 || n < max_frames_; ++n) {
      DecodedFrame d;
      const auto start = std::chrono::steady_clock::now();
      if (!source_.next(&d.frame)) break;
      d.decode_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      std::unique_lock<std::mutex> lock(mutex_);
      space_.wait(lock, [this] { return stop_ || queue_.size() < depth_; });
      if (stop_) return;
      queue_.push_back(std::move(d));
      ready_.notify_one();
    }
  } catch (...) {
    std::lock_guard<std::mutex> lock(mutex_);
    error_ = std::current_exception();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  done_ = true;
  ready_.notify_one();
}

bool FramePrefetcher::next(DecodedFrame* out) {
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait(lock, [this] { return !queue_.empty() || done_; });
  if (queue_.empty()) {
    if (error_) std::rethrow_exception(error_);
    return false;
  }
  *out = std::move(queue_.front());
  queue_.pop_front();
  space_.notify_one();
  return true;
}

}  // namespace slamcmp
