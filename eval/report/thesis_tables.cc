#include "eval/report/thesis_tables.h"

#include <cmath>

namespace slamcmp {

std::optional<ThesisVideo> thesisVideo(const std::string& name) {
  static const ThesisVideo kVideos[] = {
      {"tv1", 337, "along X (lateral to the board)", 116.31, 99.44, 483.68, 35},
      {"tv2", 335, "along Y (vertical)", 109.44, 95.26, 328.36, 0},
      {"tv3", 318, "along Z (towards and away from the board)", 110.69, 95.30, 525.16, 107},
      {"tv4", 402, "a rectangle in the XZ plane", 105.68, 92.85, 653.23, 30},
  };
  for (const auto& v : kVideos)
    if (name == v.name) return v;
  return std::nullopt;
}

double thesisMs(const ThesisVideo& video, const std::string& thesis_method) {
  if (thesis_method == "CSLAM with two-view") return video.ms_cslam_two_view;
  if (thesis_method == "CSLAM without two-view") return video.ms_cslam_calibration;
  if (thesis_method == "MonoSLAM") return video.ms_monoslam;
  return NAN;
}

}  // namespace slamcmp
