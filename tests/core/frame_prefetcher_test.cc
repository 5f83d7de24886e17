// The decode-ahead prefetcher: frames in order whatever the threads' timing, the limit on frames,
// an error at the frame that caused it, and no hang when the reader stops early.
#include "core/frame_prefetcher.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <random>
#include <stdexcept>
#include <thread>

namespace slamcmp {
namespace {

// Frames whose decoding takes a random 0-2 ms, so that threads finish out of order; frame
// `bad` (if any) throws while decoding.
class SlowSource : public FrameSource {
 public:
  SlowSource(int count, int bad = -1) : count_(count), bad_(bad) {}
  int size() const override { return count_; }
  bool claim(Frame* frame) override {
    if (next_ >= count_) return false;
    frame->index = next_++;
    frame->timestamp = 0.1 * frame->index;
    frame->grey.release();
    return true;
  }
  void decode(Frame* frame) const override {
    thread_local std::mt19937 random(std::hash<std::thread::id>()(std::this_thread::get_id()));
    std::this_thread::sleep_for(std::chrono::microseconds(random() % 2000));
    if (frame->index == bad_) throw std::runtime_error("bad frame");
    frame->grey = cv::Mat(2, 2, CV_8U, cv::Scalar(frame->index % 256));
    ++decoded_;
  }
  int decoded() const { return decoded_; }

 private:
  int count_, bad_;
  int next_ = 0;
  mutable std::atomic<int> decoded_{0};
};

TEST(FramePrefetcher, FramesComeInOrderFromSeveralThreads) {
  for (int threads : {1, 2, 3}) {
    SlowSource source(60);
    FramePrefetcher frames(source, -1, 8, threads);
    DecodedFrame d;
    int n = 0;
    while (frames.next(&d)) {
      ASSERT_EQ(d.frame.index, n) << threads << " threads";
      EXPECT_EQ(d.frame.grey.at<uint8_t>(0, 0), n % 256);
      EXPECT_GT(d.decode_ms, 0.0);
      ++n;
    }
    EXPECT_EQ(n, 60) << threads << " threads";
    EXPECT_FALSE(frames.next(&d));  // and stays at the end
  }
}

TEST(FramePrefetcher, StopsAtMaxFrames) {
  SlowSource source(60);
  FramePrefetcher frames(source, 10, 4, 3);
  DecodedFrame d;
  int n = 0;
  while (frames.next(&d)) ++n;
  EXPECT_EQ(n, 10);
  EXPECT_LE(source.decoded(), 10);
}

TEST(FramePrefetcher, AnErrorComesAtItsFrameAfterTheFramesBefore) {
  SlowSource source(60, 17);
  FramePrefetcher frames(source, -1, 8, 3);
  DecodedFrame d;
  int n = 0;
  try {
    while (frames.next(&d)) ++n;
    FAIL() << "the error was not rethrown";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "bad frame");
  }
  EXPECT_EQ(n, 17);
  EXPECT_FALSE(frames.next(&d));  // nothing after the error
}

TEST(FramePrefetcher, KeepsWithinDepthAndStopsWhenDestroyedEarly) {
  SlowSource source(1000);
  {
    FramePrefetcher frames(source, -1, 5, 3);
    DecodedFrame d;
    ASSERT_TRUE(frames.next(&d));
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // the threads fill the depth, then wait
    EXPECT_LE(source.decoded(), 1 + 5);
  }  // destroyed with frames pending: joins without hanging
  EXPECT_LT(source.decoded(), 1000);
}

}  // namespace
}  // namespace slamcmp
