#pragma once
// The process's interrupt request (Ctrl-C, SIGTERM, SIGHUP): set from the signal handler the
// application installs (eval/app/run_sequence.h), polled by runs between frames and by long reads
// (an image list of a million lines) so that an interruption is said as such, never as "no frames".
#include <stdexcept>

namespace slamcmp {

void requestInterrupt();  // async-signal-safe
bool interruptRequested();

// A command stopped by Ctrl-C, SIGTERM or SIGHUP once it wrote what it had (a run's outputs marked
// "interrupted", a compare's report marking the runs not finished), or while it was still reading
// its inputs: main exits 130, as a shell reports a command stopped by Ctrl-C, so that a script does
// not take it for a finished one, nor for bad input.
class Interrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace slamcmp
