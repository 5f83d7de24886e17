#pragma once
// A one-line progress display on stderr, shown only when stderr is a terminal.
#include <chrono>
#include <string>

namespace slamcmp {

class Progress {
 public:
  // total < 0: unknown.
  Progress(std::string label, int total);
  ~Progress();
  void update(int done, const std::string& detail = "");
  void finish();

 private:
  std::string label_;
  int total_;
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace slamcmp
