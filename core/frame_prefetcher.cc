#include "core/frame_prefetcher.h"

#include <algorithm>
#include <chrono>

namespace slamcmp {

FramePrefetcher::FramePrefetcher(FrameSource& source, int max_frames, int depth, int threads)
    : source_(source), max_frames_(max_frames), depth_(std::max(1, depth)) {
  if (threads <= 0) threads = static_cast<int>(std::clamp(std::thread::hardware_concurrency(), 1u, 3u));
  for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { work(); });
}

FramePrefetcher::~FramePrefetcher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  space_.notify_all();
  for (std::thread& t : threads_) t.join();
}

int FramePrefetcher::claim(Slot* slot) {
  std::lock_guard<std::mutex> lock(source_mutex_);
  if (source_done_) return -1;
  const int position = next_position_;
  bool more = false;
  try {
    more = (max_frames_ < 0 || position < max_frames_) && source_.claim(&slot->decoded.frame);
  } catch (...) {  // the source cannot go on: this position reports why
    slot->error = std::current_exception();
    source_done_ = true;
    ++next_position_;
    return position;
  }
  if (!more) {
    source_done_ = true;
    return -1;
  }
  ++next_position_;
  return position;
}

void FramePrefetcher::work() {
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      space_.wait(lock, [this] { return stop_ || end_ >= 0 || reserved_ < depth_; });
      if (stop_ || end_ >= 0) return;
      ++reserved_;  // before claiming, so that all the threads together keep within depth
    }
    Slot slot;
    const auto start = std::chrono::steady_clock::now();
    const int position = claim(&slot);
    if (position < 0) {
      std::lock_guard<std::mutex> lock(mutex_);
      --reserved_;
      if (end_ < 0) {
        std::lock_guard<std::mutex> source_lock(source_mutex_);
        end_ = next_position_;
      }
      ready_.notify_all();
      space_.notify_all();
      return;
    }
    if (!slot.error) {
      try {
        source_.decode(&slot.decoded.frame);
      } catch (...) {
        slot.error = std::current_exception();
      }
    }
    slot.decoded.decode_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    std::lock_guard<std::mutex> lock(mutex_);
    slots_.emplace(position, std::move(slot));
    ready_.notify_all();
  }
}

bool FramePrefetcher::next(DecodedFrame* out) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto at_end = [this] { return end_ >= 0 && consumed_ >= end_; };
  ready_.wait(lock, [&] { return at_end() || slots_.count(consumed_); });
  if (at_end()) return false;
  const auto it = slots_.find(consumed_);
  Slot slot = std::move(it->second);
  slots_.erase(it);
  ++consumed_;
  --reserved_;
  space_.notify_all();
  if (slot.error) {
    end_ = consumed_;  // nothing after an error
    std::rethrow_exception(slot.error);
  }
  *out = std::move(slot.decoded);
  return true;
}

}  // namespace slamcmp
