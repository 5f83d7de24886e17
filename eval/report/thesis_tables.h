#pragma once
// The thesis's Tables 3.1 and 3.2 (Jogle 2009), printed beside what this machine measures.
#include <optional>
#include <string>

namespace slamcmp {

struct ThesisVideo {
  const char* name;
  int frames;
  const char* motion;
  // Table 3.2, ms per frame on a 2009 dual-core Athlon 64 X2.
  double ms_cslam_two_view, ms_cslam_calibration, ms_monoslam;
  // Frame after which the thesis's MonoSLAM lost every feature (0: it did not).
  int monoslam_lost_after;
};

// Table 3.2's column for "CSLAM with two-view", "CSLAM without two-view" or "MonoSLAM"; NaN for
// another name.
double thesisMs(const ThesisVideo& video, const std::string& thesis_method);

// tv1..tv4, or nothing for another sequence name.
std::optional<ThesisVideo> thesisVideo(const std::string& name);

}  // namespace slamcmp
