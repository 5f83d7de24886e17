#pragma once
// One exception type for bad input: thrown where the problem is found, caught once in main,
// printed as one line, exit code 2.
#include <stdexcept>
#include <string>

namespace slamcmp {

class InputError : public std::runtime_error {
 public:
  // `where` names the file (and line or field); `what` says what is wrong.
  InputError(const std::string& where, const std::string& what)
      : std::runtime_error(where.empty() ? what : where + ": " + what) {}
};

// "file:line" for messages about one line of a text file.
inline std::string atLine(const std::string& path, int line) {
  return path + ":" + std::to_string(line);
}

}  // namespace slamcmp
