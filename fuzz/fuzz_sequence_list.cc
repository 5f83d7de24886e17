// libFuzzer target: the sequence lists, through openSequence on a folder holding two small images
// (0.png, 1.png) for the lines to name. An even first byte makes the rest rgb.txt (TUM), an odd
// one mav0/cam0/data.csv (EuRoC, images in mav0/cam0/data/).
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "core/error.h"
#include "core/sequence.h"
#include "fuzz/fuzz_input.h"

namespace {

std::string sequenceFolder() {
  static const std::string dir = [] {
    const auto root = slamcmp::fuzz::workDir() / "seq";
    const cv::Mat grey(8, 8, CV_8UC1, cv::Scalar(128));
    for (const auto& d : {root, root / "mav0" / "cam0" / "data"}) {
      std::filesystem::create_directories(d);
      cv::imwrite((d / "0.png").string(), grey);
      cv::imwrite((d / "1.png").string(), grey);
    }
    return root.string();
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace slamcmp;
  if (size < 1) return 0;
  const std::string dir = sequenceFolder();
  const bool tum = data[0] % 2 == 0;
  std::error_code ec;
  std::filesystem::remove(dir + "/rgb.txt", ec);
  std::filesystem::remove(dir + "/mav0/cam0/data.csv", ec);
  fuzz::writeInput(tum ? "seq/rgb.txt" : "seq/mav0/cam0/data.csv", data + 1, size - 1);
  try {
    Sequence seq = openSequence(dir);
    Frame frame;
    while (seq.frames->next(&frame)) {
    }
  } catch (const InputError&) {  // the expected answer to bad input; anything else is a finding
  }
  return 0;
}
