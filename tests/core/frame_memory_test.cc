#include "core/frame_memory.h"

#include <sys/resource.h>

#include <memory>
#include <vector>

#include <gtest/gtest.h>

namespace slamcmp {
namespace {

long minorFaults() {
  rusage usage{};
  getrusage(RUSAGE_THREAD, &usage);
  return usage.ru_minflt;
}

// One frame's work: five 640x480 float planes allocated, every page written, freed together (as
// cv::cornerMinEigenVal's buffers are). Returns the pages faulted in meanwhile.
long frameBuffersFaults() {
  constexpr size_t kPlane = 640 * 480 * sizeof(float);
  const long before = minorFaults();
  std::vector<std::unique_ptr<char[]>> planes;
  for (int k = 0; k < 5; ++k) {
    planes.emplace_back(new char[kPlane]);
    for (size_t i = 0; i < kPlane; i += 4096) planes.back()[i] = static_cast<char>(i);
  }
  volatile char sink = planes.back()[kPlane / 2];  // the buffers are used
  (void)sink;
  return minorFaults() - before;
}

// With glibc's defaults the third frame's buffers, like every frame's, are faulted in again (about
// 1500 pages: this test fails so without the call).
TEST(FrameMemory, AFrameFreedBuffersAreReusedWithoutFaultingTheirPagesIn) {
  if (!keepFreedMemoryForReuse())
    GTEST_SKIP() << "the thresholds are not set here (not glibc, AddressSanitizer, or the user's malloc settings)";
  frameBuffersFaults();
  frameBuffersFaults();
  EXPECT_LT(frameBuffersFaults(), 64) << "pages faulted in again, of 1500";
}

}  // namespace
}  // namespace slamcmp
