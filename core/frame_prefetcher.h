#pragma once
// Decodes frames ahead on a second thread while the tracker works on the current one, so a run
// costs little more than decoding alone. Errors in the decoding thread (InputError for an image of
// the wrong size) are rethrown by next() in the caller's thread.
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

#include "core/sequence.h"

namespace slamcmp {

struct DecodedFrame {
  Frame frame;
  double decode_ms = 0;
};

class FramePrefetcher {
 public:
  // Reads at most max_frames (< 0: all) from `source`, keeping up to `depth` frames ready.
  FramePrefetcher(FrameSource& source, int max_frames, int depth = 4);
  ~FramePrefetcher();
  FramePrefetcher(const FramePrefetcher&) = delete;
  FramePrefetcher& operator=(const FramePrefetcher&) = delete;

  // The next frame in order; false at the end.
  bool next(DecodedFrame* out);

 private:
  void run();

  FrameSource& source_;
  const int max_frames_;
  const size_t depth_;
  std::mutex mutex_;
  std::condition_variable ready_, space_;
  std::deque<DecodedFrame> queue_;
  bool done_ = false;
  bool stop_ = false;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace slamcmp
