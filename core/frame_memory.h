#pragma once
// Memory a frame's work frees, kept for the next frame. glibc gives blocks over its mmap threshold
// (128 KB at first) back to the kernel when they are freed, and trims the free top of its heap, so
// the frame-sized buffers OpenCV allocates inside each call (cornerMinEigenVal: derivatives and their
// products, five 640x480 float planes) are faulted in again, page by page, in every call. On the
// machine this project runs on, goodFeaturesToTrack on a 640x480 frame took 26 ms so, and 3 ms with
// the memory kept (docs/findings.md, session 34).
namespace slamcmp {

// Raises both thresholds for the whole process, unless GLIBC_TUNABLES is set (the user's settings
// win). Call once at the start of a process that tracks frames (slamcmp, the benchmarks, the tests),
// before it starts threads. Elsewhere than glibc it does nothing.
void keepFreedMemoryForReuse();

}  // namespace slamcmp
