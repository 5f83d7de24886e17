#pragma once
// Writes a run's outputs (SPEC section 4): trajectory.txt and frames.csv line by line as frames
// are tracked (an interrupted run leaves valid files for the frames done), summary.json and
// map.ply at the end.
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/tracker.h"
#include "core/trajectory.h"

namespace slamcmp {

struct TimingStats {
  double median = 0, mean = 0, p99 = 0, max = 0;  // milliseconds
};
TimingStats timingStats(std::vector<double> ms);

class RunRecorder {
 public:
  // Creates `out_dir` (and parents); throws InputError if it cannot be written.
  RunRecorder(const std::string& out_dir, const std::string& backend);

  void record(const Frame& frame, const FrameResult& result, double ms, double decode_ms);
  // A frame whose image could not be decoded: recorded lost, not fatal.
  void recordUndecodable(const Frame& frame, double decode_ms);

  // summary.json: the SPEC fields, plus `extra` merged in (options, metrics, ...).
  nlohmann::json summary() const;
  // Writes summary() with `extra` merged in to summary.json and returns what it wrote.
  nlohmann::json writeSummary(const nlohmann::json& extra) const;

  const std::string& outDir() const { return out_dir_; }
  const Trajectory& trajectory() const { return trajectory_; }
  int frames() const { return frames_; }
  int tracked() const { return static_cast<int>(trajectory_.size()); }

 private:
  void writeRow(const Frame& frame, TrackStatus status, double ms, double decode_ms, int features,
                int measured);

  std::string out_dir_;
  std::string backend_;
  std::ofstream trajectory_file_;
  std::ofstream frames_file_;
  Trajectory trajectory_;
  std::vector<double> ms_;
  int frames_ = 0;
  int lost_ = 0;
  std::optional<int> first_lost_frame_;
  std::map<std::string, int> lost_reasons_;
};

// PLY (ASCII) with x y z, id, observations and sigma per point; MeshLab, CloudCompare, Open3D.
void writeMapPly(const std::string& path, const std::vector<MapPoint>& points);

}  // namespace slamcmp
