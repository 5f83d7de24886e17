// libFuzzer target: readTrajectory in every format. The first byte picks the format (auto, TUM,
// EuRoC, KITTI, KITTI with a times file); for the last, the bytes after the first NUL are the times.
#include <cstring>

#include "core/error.h"
#include "core/trajectory.h"
#include "fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace slamcmp;
  if (size < 1) return 0;
  const int mode = data[0] % 5;
  ++data, --size;
  try {
    switch (mode) {
      case 0:
        readTrajectory(fuzz::writeInput("traj.txt", data, size));
        break;
      case 1:
        readTrajectory(fuzz::writeInput("traj.txt", data, size), TrajectoryFormat::Tum);
        break;
      case 2:
        readTrajectory(fuzz::writeInput("traj.csv", data, size));
        break;
      case 3:
        readTrajectory(fuzz::writeInput("traj.txt", data, size), TrajectoryFormat::Kitti);
        break;
      default: {
        const auto* nul = static_cast<const uint8_t*>(std::memchr(data, 0, size));
        const size_t poses = nul ? static_cast<size_t>(nul - data) : size;
        const std::string times = nul ? fuzz::writeInput("times.txt", nul + 1, size - poses - 1)
                                      : fuzz::writeInput("times.txt", data, 0);
        readTrajectory(fuzz::writeInput("traj.txt", data, poses), TrajectoryFormat::Kitti, times);
      }
    }
  } catch (const InputError&) {  // the expected answer to bad input; anything else is a finding
  }
  return 0;
}
