#pragma once
// printf into a std::string of whatever length the values need: a file line must never be cut
// at a buffer's size (a timestamp of 1e300 s prints 300 digits with %f).
#include <string>

namespace slamcmp {

std::string formatString(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace slamcmp
