#include "core/run_recorder.h"

#include <algorithm>
#include <filesystem>
#include <regex>

#include "core/error.h"
#include "core/frames_csv.h"
#include "core/run_files.h"
#include "core/statistics.h"

namespace slamcmp {

std::string reasonCategory(const std::string& reason) {
  static const std::regex number(R"([-+]?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?)");
  return std::regex_replace(reason, number, "#");
}

RunRecorder::RunRecorder(const std::string& out_dir, const std::string& backend)
    : out_dir_(out_dir), backend_(backend) {
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw InputError(out_dir, "output folder cannot be created: " + ec.message());
  const std::string traj = trajectoryPath();
  trajectory_file_.open(traj);
  if (!trajectory_file_) throw InputError(traj, "cannot be written");
  trajectory_file_ << "# timestamp tx ty tz qx qy qz qw (T_world_camera, " << backend << ")\n";
  const std::string frames = out_dir + "/" + run_files::kFrames;
  frames_file_.open(frames);
  if (!frames_file_) throw InputError(frames, "cannot be written");
  frames_file_ << framesCsvHeader() << '\n';
  trajectory_file_.flush();  // valid (empty) files even while the first rows wait
  frames_file_.flush();
}

void RunRecorder::write(Row row) {
  if (row.T_world_camera && !row.T_world_camera->isFinite()) {  // the last line of defence: no NaN pose
    row.T_world_camera.reset();
    row.status = TrackStatus::Lost;
    row.reason = "the back-end's pose is not finite";
  }
  // Unposed: initialising (not started yet: waiting, not lost) or lost.
  const TrackStatus status = row.T_world_camera || row.status == TrackStatus::Initialising ? row.status
                                                                                          : TrackStatus::Lost;
  if (row.T_world_camera) {
    ++tracked_;
    trajectory_file_ << formatTumLine({row.timestamp, *row.T_world_camera}) << '\n';
    trajectory_file_.flush();
  } else {
    const bool initialising = status == TrackStatus::Initialising;
    ++(initialising ? initialising_ : lost_);
    if (!initialising && !first_lost_frame_) first_lost_frame_ = row.index;
    ++(initialising ? initialising_reasons_ : lost_reasons_)[row.reason.empty() ? std::string(toString(status))
                                                                                : reasonCategory(row.reason)];
  }
  frames_file_ << formatFrameRow({row.index, row.timestamp, status, row.source, row.ms, row.cpu_ms, row.decode_ms,
                                  row.features, row.measured, row.reason});
  frames_file_.flush();
}

void RunRecorder::record(const Frame& frame, const FrameResult& r, double ms, double cpu_ms, double decode_ms) {
  ++frames_;
  ms_.push_back(ms);
  cpu_ms_.push_back(cpu_ms);
  for (const auto& [stage, stage_ms] : r.stages) stage_ms_[stage].push_back(stage_ms);
  const Row row{frame.index, frame.timestamp, r.status, r.source, r.T_world_camera, r.features, r.measured,
                r.reason, ms, cpu_ms, decode_ms};
  // The late poses first: the frame bringing them may itself be unposed (a calibration accepted in
  // a frame whose own start failed), and they would be lost with it.
  for (const LatePose& late : r.late_poses) {
    const auto at = std::find_if(waiting_.begin(), waiting_.end(),
                                 [&](const Row& w) { return w.index == late.frame_index; });
    if (at == waiting_.end()) continue;  // not an Initialising frame: its row stands
    at->status = TrackStatus::Tracked;
    at->source = late.source;
    at->T_world_camera = late.T_world_camera;
    at->measured = late.measured;
    at->reason.clear();
  }
  if (r.status == TrackStatus::Initialising && !r.T_world_camera) {
    waiting_.push_back(row);
    return;
  }
  flush();
  write(row);
}

void RunRecorder::recordUndecodable(const Frame& frame, double decode_ms) {
  ++frames_;
  const Row row{frame.index, frame.timestamp, TrackStatus::Lost, "", std::nullopt, 0, 0,
                "image could not be decoded", 0.0, 0.0, decode_ms};
  if (waiting_.empty()) write(row);
  else waiting_.push_back(row);  // keeps the files in frame order
}

void RunRecorder::flush() {
  for (const Row& row : waiting_) write(row);
  waiting_.clear();
}

nlohmann::json RunRecorder::summary() const {
  // No frame timed (a run interrupted before its first): null, not NaN, which JSON has not.
  const auto timing = [](const std::vector<double>& ms) {
    const Statistics s = computeStatistics(ms);
    const auto number = [&s](double v) { return s.count > 0 ? nlohmann::json(v) : nlohmann::json(nullptr); };
    return nlohmann::json{{"median", number(s.median)}, {"mean", number(s.mean)}, {"p99", number(s.p99)},
                          {"max", number(s.max)}};
  };
  nlohmann::json j;
  j["backend"] = backend_;
  j["frames"] = frames_;
  j["tracked"] = tracked();
  j["lost"] = lost_;
  j["initialising"] = initialising_;
  j["first_lost_frame"] = first_lost_frame_ ? nlohmann::json(*first_lost_frame_) : nlohmann::json(nullptr);
  j["ms_per_frame"] = timing(ms_);
  j["cpu_ms_per_frame"] = timing(cpu_ms_);
  nlohmann::json stages = nlohmann::json::object();
  for (const auto& [stage, calls] : stage_ms_) {
    const Statistics st = computeStatistics(calls);
    stages[stage] = {{"median", st.median}, {"mean", st.mean}, {"p99", st.p99}, {"max", st.max},
                     {"calls", static_cast<int>(calls.size())}};
  }
  j["stages"] = stages;
  j["lost_reasons"] = lost_reasons_;
  j["initialising_reasons"] = initialising_reasons_;
  return j;
}

nlohmann::json RunRecorder::writeSummary(const nlohmann::json& extra) {
  flush();
  nlohmann::json j = summary();
  j.update(extra);
  const std::string path = out_dir_ + "/" + run_files::kSummary;
  std::ofstream out(path);
  if (!out) throw InputError(path, "cannot be written");
  out << j.dump(2) << '\n';
  if (!out) throw InputError(path, "write failed");
  return j;
}

}  // namespace slamcmp
