#pragma once
// Writes a run's outputs (SPEC section 4): trajectory.txt and frames.csv line by line as frames
// are tracked (an interrupted run leaves valid files for the frames done), summary.json at the
// end (map.ply: core/map_ply.h). Rows of Initialising frames wait until a frame that is not; any
// frame's FrameResult::late_poses (an Initialising one's too) may pose them, so both files stay in
// frame order.
#include <fstream>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/run_files.h"
#include "core/tracker.h"
#include "core/trajectory.h"

namespace slamcmp {

// A lost frame's reason with its numbers replaced by '#': summary.json counts lost frames by
// category ("too few inliers (# of #)"), so the count stays small over any number of frames.
std::string reasonCategory(const std::string& reason);

class RunRecorder {
 public:
  // Creates `out_dir` (and parents); throws InputError if it cannot be written.
  RunRecorder(const std::string& out_dir, const std::string& backend);

  // ms: the back-end's wall time for the frame; cpu_ms: its thread's CPU time.
  void record(const Frame& frame, const FrameResult& result, double ms, double cpu_ms, double decode_ms);
  // A frame whose image could not be decoded: recorded lost, not fatal.
  void recordUndecodable(const Frame& frame, double decode_ms);
  // Writes the rows still waiting (the run ended, or stopped, while initialising).
  void flush();

  // summary.json: the SPEC fields over the rows written, plus `extra` merged in (options, metrics, ...).
  nlohmann::json summary() const;
  // flush(), then writes summary() with `extra` merged in to summary.json and returns what it wrote.
  nlohmann::json writeSummary(const nlohmann::json& extra);

  // trajectory.txt, complete up to the last recorded frame (the poses are not kept in memory, so
  // a long run's memory stays flat).
  std::string trajectoryPath() const { return out_dir_ + "/" + run_files::kTrajectory; }
  int frames() const { return frames_; }  // recorded, written or waiting
  int tracked() const { return tracked_; }  // posed among the rows written

 private:
  struct Row {
    int index = 0;
    double timestamp = 0;
    TrackStatus status = TrackStatus::Lost;
    std::string source;
    std::optional<SE3> T_world_camera;
    int features = 0, measured = 0;
    std::string reason;
    double ms = 0, cpu_ms = 0, decode_ms = 0;
  };
  void write(Row row);

  std::vector<Row> waiting_;  // Initialising rows (and undecodable ones among them), in order
  std::string out_dir_;
  std::string backend_;
  std::ofstream trajectory_file_;
  std::ofstream frames_file_;
  std::vector<double> ms_, cpu_ms_;
  std::map<std::string, std::vector<double>> stage_ms_;  // CPU ms of each call of each stage
  int frames_ = 0;
  int tracked_ = 0;
  // Frames without a pose: lost (the back-end had started) or initialising (not yet), each with
  // its reasons by category (numbers as '#').
  int lost_ = 0;
  int initialising_ = 0;
  std::optional<int> first_lost_frame_;
  std::map<std::string, int> lost_reasons_;
  std::map<std::string, int> initialising_reasons_;
};

}  // namespace slamcmp
