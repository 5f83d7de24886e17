// The tests' main: frame buffers reused as in slamcmp (core/frame_memory.h), so that the in-process
// runs behave and cost as `slamcmp run` does.
#include <gtest/gtest.h>

#include "core/frame_memory.h"

int main(int argc, char** argv) {
  slamcmp::keepFreedMemoryForReuse();
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
