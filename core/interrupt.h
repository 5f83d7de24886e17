#pragma once
// The process's interrupt request (Ctrl-C, SIGTERM, SIGHUP): set from the signal handler the
// application installs (eval/app/run_sequence.h), polled by runs between frames and by long reads
// (an image list of a million lines) so that an interruption is said as such, never as "no frames".
namespace slamcmp {

void requestInterrupt();  // async-signal-safe
bool interruptRequested();

}  // namespace slamcmp
