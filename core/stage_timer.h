#pragma once
// Per-stage timing of a back-end (SPEC section 4, summary.json `stages`): a scope's CPU time on the
// tracking thread, added to the frame's stage list under the back-end's own stage name.
#include <ctime>
#include <string>
#include <utility>
#include <vector>

namespace slamcmp {

using StageTimes = std::vector<std::pair<std::string, double>>;  // stage name, CPU ms (in call order)

inline double threadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e3 * static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_nsec);
}

class StageTimer {
 public:
  StageTimer(StageTimes* times, const char* stage) : times_(times), stage_(stage), start_(threadCpuMs()) {}
  ~StageTimer() { times_->emplace_back(stage_, threadCpuMs() - start_); }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  StageTimes* times_;
  const char* stage_;
  double start_;
};

}  // namespace slamcmp
