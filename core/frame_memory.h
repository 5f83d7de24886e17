#pragma once
// Memory a frame's work frees, kept for the next frame. glibc gives blocks over its mmap threshold
// back to the kernel when they are freed, and trims the free top of its heap, so the frame-sized
// buffers OpenCV allocates and frees inside each call (cornerMinEigenVal: derivatives and their
// products, five 640x480 float planes) are faulted in again, page by page, in every call. On this
// project's machine Shi-Tomasi on a 640x480 frame took 24-34 ms that way and 3.2-3.7 ms with the
// memory kept (docs/findings.md, session 34).
namespace slamcmp {

// Raises both thresholds for the whole process. The user's malloc settings win: nothing is changed
// when GLIBC_TUNABLES sets a glibc.malloc tunable or MALLOC_MMAP_THRESHOLD_ or
// MALLOC_TRIM_THRESHOLD_ is set. Call once at the start of a process that tracks frames (slamcmp,
// decode_only, the benchmarks, the tests), before it starts threads. Returns whether the thresholds
// were set (not elsewhere than glibc, nor under AddressSanitizer, whose allocator ignores them).
bool keepFreedMemoryForReuse();

}  // namespace slamcmp
