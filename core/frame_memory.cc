#include "core/frame_memory.h"

#include <cstdlib>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace slamcmp {

void keepFreedMemoryForReuse() {
#if defined(__GLIBC__)
  if (std::getenv("GLIBC_TUNABLES")) return;
  // glibc's largest mmap threshold (32 MB on 64-bit): a block under it comes from the heap and, once
  // freed, stays there for the next; the heap keeps up to 256 MB of free top (its peak is the run's).
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

}  // namespace slamcmp
