#pragma once
// libpng and libjpeg print their complaints about a corrupt image straight to the process's
// stderr, before (and besides) the one line slamcmp says about it. Decoding runs with stderr
// captured instead: the text becomes part of our message, or is dropped when the image is whole.
#include <functional>
#include <mutex>
#include <string>

namespace slamcmp {

// Runs `f` with file descriptor 2 pointed at a private file and returns what was written to it.
// The descriptor is the process's: one capture runs at a time, and our own writers that may run
// meanwhile on another thread (core/progress.cc) hold stderrMutex() while they write.
std::string captureStderr(const std::function<void()>& f);
std::mutex& stderrMutex();

}  // namespace slamcmp
