#include "core/stderr_capture.h"

#include <unistd.h>

#include <cstdio>

namespace slamcmp {

std::mutex& stderrMutex() {
  static std::mutex m;
  return m;
}

std::string captureStderr(const std::function<void()>& f) {
  const std::lock_guard<std::mutex> lock(stderrMutex());
  static std::FILE* const sink = std::tmpfile();  // one for the process, emptied for each capture
  std::fflush(stderr);
  const int saved = sink ? dup(2) : -1;
  if (saved < 0 || ftruncate(fileno(sink), 0) != 0 || lseek(fileno(sink), 0, SEEK_SET) != 0 ||
      dup2(fileno(sink), 2) < 0) {
    if (saved >= 0) close(saved);
    f();  // no capture possible: the libraries' lines get through, nothing else changes
    return {};
  }
  const auto restore = [saved] {
    std::fflush(stderr);
    dup2(saved, 2);
    close(saved);
  };
  try {
    f();
  } catch (...) {
    restore();
    throw;
  }
  restore();
  std::string text;
  std::rewind(sink);
  char buffer[512];
  for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, sink)) > 0;) text.append(buffer, n);
  return text;
}

}  // namespace slamcmp
