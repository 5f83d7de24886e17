#pragma once
// One exception type for bad input: thrown where the problem is found, caught once in main,
// printed as one line, exit code 2.
#include <stdexcept>
#include <string>
#include <utility>

namespace slamcmp {

class InputError : public std::runtime_error {
 public:
  // `where` names the file (and line or field); `what` says what is wrong.
  InputError(const std::string& where, const std::string& what)
      : std::runtime_error(where.empty() ? what : where + ": " + what) {}
};

// Thrown by an options struct's check(): `field` as spelt in its visit(), without a path.
class OptionError : public std::runtime_error {
 public:
  OptionError(std::string field, const std::string& what)
      : std::runtime_error(what), field_(std::move(field)) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

// "file:line" for messages about one line of a text file.
inline std::string atLine(const std::string& path, int line) {
  return path + ":" + std::to_string(line);
}

}  // namespace slamcmp
