#include "core/frame_memory.h"

#include <sys/resource.h>

#include <cstdlib>
#include <memory>

#include <gtest/gtest.h>

namespace slamcmp {
namespace {

long minorFaults() {
  rusage usage{};
  getrusage(RUSAGE_THREAD, &usage);
  return usage.ru_minflt;
}

// Allocates a block, writes every page of it and frees it, as one frame's buffer.
void useBuffer(size_t bytes) {
  std::unique_ptr<char[]> buffer(new char[bytes]);
  for (size_t i = 0; i < bytes; i += 4096) buffer[i] = static_cast<char>(i);
  volatile char sink = buffer[bytes / 2];
  (void)sink;
}

// glibc's defaults give a freed 8 MB block back to the kernel, and its next allocation is faulted in
// again, all 2048 pages (this test fails so without the call).
TEST(FrameMemory, AFreedFrameBufferIsReusedWithoutFaultingItsPagesIn) {
#if !defined(__GLIBC__)
  GTEST_SKIP() << "the thresholds are glibc's";
#endif
  if (std::getenv("GLIBC_TUNABLES")) GTEST_SKIP() << "GLIBC_TUNABLES is set: the user's malloc settings win";
  keepFreedMemoryForReuse();
  constexpr size_t kBytes = 8 << 20;
  useBuffer(kBytes);
  const long before = minorFaults();
  useBuffer(kBytes);
  EXPECT_LT(minorFaults() - before, 64) << "pages faulted in again of " << kBytes / 4096;
}

}  // namespace
}  // namespace slamcmp
