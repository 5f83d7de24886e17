#include "core/interrupt.h"

#include <atomic>

namespace slamcmp {

namespace {
std::atomic<bool> g_interrupt{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");
}  // namespace

void requestInterrupt() { g_interrupt = true; }
bool interruptRequested() { return g_interrupt; }

}  // namespace slamcmp
