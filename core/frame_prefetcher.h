#pragma once
// Decodes frames ahead on other threads while the tracker works on the current one, so a run
// costs little more than decoding alone. Image files decode on several threads at once (a frame
// decodes in twice the time the tracker takes), handed out in order. An error while decoding (an
// image of the wrong size) is rethrown by next() at that frame, in the caller's thread.
#include <condition_variable>
#include <exception>
#include <map>
#include <mutex>
#include <thread>
#include <vector>

#include "core/sequence.h"

namespace slamcmp {

struct DecodedFrame {
  Frame frame;
  double decode_ms = 0;
};

class FramePrefetcher {
 public:
  // Reads at most max_frames (< 0: all) from `source`, keeping up to `depth` frames ready or being
  // decoded, on `threads` threads (0: as many as cores, at most 3).
  FramePrefetcher(FrameSource& source, int max_frames, int depth = 8, int threads = 0);
  ~FramePrefetcher();
  FramePrefetcher(const FramePrefetcher&) = delete;
  FramePrefetcher& operator=(const FramePrefetcher&) = delete;

  // The next frame in order; false at the end.
  bool next(DecodedFrame* out);

 private:
  struct Slot {
    DecodedFrame decoded;
    std::exception_ptr error;
  };
  void work();
  // Takes the source's next frame into *slot; its position, or -1 at the end.
  int claim(Slot* slot);

  FrameSource& source_;
  const int max_frames_;
  const int depth_;

  std::mutex source_mutex_;  // claim() order: positions and the source's own state
  int next_position_ = 0;
  bool source_done_ = false;

  std::mutex mutex_;  // everything below
  std::condition_variable ready_, space_;
  std::map<int, Slot> slots_;  // decoded, by position, waiting for next()
  int consumed_ = 0;           // positions handed out by next()
  int reserved_ = 0;           // positions claimed or about to be, not yet handed out
  int end_ = -1;               // the number of frames, once the source is done
  bool stop_ = false;
  std::vector<std::thread> threads_;
};

}  // namespace slamcmp
