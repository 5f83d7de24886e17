#pragma once
// The files a run writes into its folder (README, "The command line"), spelt once for the writers
// (the run recorder, `run`) and for `compare`, which reads them back.
namespace slamcmp::run_files {

inline constexpr const char* kTrajectory = "trajectory.txt";  // TUM, the posed frames
inline constexpr const char* kFrames = "frames.csv";          // every frame: status, reason, timing
inline constexpr const char* kSummary = "summary.json";
inline constexpr const char* kMap = "map.ply";
inline constexpr const char* kKeyframes = "keyframes.txt";  // TUM, a back-end's refined keyframes
inline constexpr const char* kNees = "nees.csv";  // with ground truth and a covariance
inline constexpr const char* kOverlay = "overlay.csv";  // with --overlay

}  // namespace slamcmp::run_files
