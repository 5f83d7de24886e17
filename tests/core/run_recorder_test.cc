// The run outputs of SPEC section 4: trajectory.txt, frames.csv and summary.json, read back as a
// user (or eval) would (map.ply: map_ply_test.cc).
#include "core/run_recorder.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/frames_csv.h"
#include "core/trajectory.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

using test::readLines;

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream ss(line);
  for (std::string f; std::getline(ss, f, ',');) fields.push_back(f);
  return fields;
}

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

Frame frameAt(int index) {
  Frame f;
  f.index = index;
  f.timestamp = 10.0 + 0.1 * index;
  return f;
}

FrameResult tracked(const std::string& source, const SE3& T, int features, int measured) {
  FrameResult r;
  r.status = TrackStatus::Tracked;
  r.source = source;
  r.T_world_camera = T;
  r.features = features;
  r.measured = measured;
  return r;
}

FrameResult lost(const std::string& reason) {
  FrameResult r;
  r.status = TrackStatus::Lost;
  r.reason = reason;
  return r;
}

TEST(RunRecorder, RecordsTrackedLostAndUndecodableFrames) {
  test::TempDir dir;
  const std::string out = dir.file("runs/seq-test");  // parents are created
  const SE3 T0 = SE3::fromRotvec(Vec3(0.1, -0.2, 0.3), Vec3(0.5, 0.25, -1.0));
  const SE3 T2 = SE3::fromRotvec(Vec3(0.15, -0.2, 0.3), Vec3(0.6, 0.25, -1.0));
  {
    RunRecorder recorder(out, "cslam");
    recorder.record(frameAt(0), tracked("board", T0, 54, 54), 5.0, 2.5, 1.5);
    recorder.record(frameAt(1), lost("board not found"), 1.0, 0.5, 1.25);
    recorder.record(frameAt(2), tracked("two_view", T2, 120, 80), 3.0, 1.5, 1.0);
    recorder.recordUndecodable(frameAt(3), 0.5);
    FrameResult initialising;
    initialising.status = TrackStatus::Initialising;
    recorder.record(frameAt(4), initialising, 4.0, 2.0, 1.0);
    EXPECT_EQ(recorder.frames(), 5);
    EXPECT_EQ(recorder.tracked(), 2);
    recorder.writeSummary({{"sequence", "seq"}});
  }

  // trajectory.txt: only the frames with a pose, readable as TUM.
  const Trajectory t = readTrajectory(out + "/trajectory.txt");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_NEAR(t[0].timestamp, 10.0, 1e-9);
  EXPECT_NEAR(t[1].timestamp, 10.2, 1e-9);
  EXPECT_LT((t[1].T_world_camera.t() - T2.t()).norm(), 1e-9);
  EXPECT_LT(rotationAngle(t[0].T_world_camera.R().transpose() * T0.R()), 1e-8);

  // frames.csv: the SPEC header and one row a frame.
  const auto lines = readLines(out + "/frames.csv");
  ASSERT_EQ(lines.size(), 6u);
  EXPECT_EQ(lines[0], "frame,timestamp,status,ms,cpu_ms,decode_ms,features,measured,reason");
  const std::vector<std::string> status = {"board", "lost", "two_view", "lost", "initialising"};
  for (int i = 0; i < 5; ++i) {
    const auto f = splitCsv(lines[i + 1]);
    ASSERT_GE(f.size(), 8u) << lines[i + 1];
    EXPECT_EQ(std::stoi(f[0]), i);
    EXPECT_NEAR(std::stod(f[1]), 10.0 + 0.1 * i, 1e-6);
    EXPECT_EQ(f[2], status[i]);
  }
  const auto row2 = splitCsv(lines[3]);
  EXPECT_DOUBLE_EQ(std::stod(row2[3]), 3.0);
  EXPECT_DOUBLE_EQ(std::stod(row2[4]), 1.5);  // cpu_ms
  EXPECT_DOUBLE_EQ(std::stod(row2[5]), 1.0);
  EXPECT_EQ(row2[6], "120");
  EXPECT_EQ(row2[7], "80");

  // Each frame's own reason, read back.
  const std::vector<FrameRow> rows = readFramesCsv(out + "/frames.csv");
  ASSERT_EQ(rows.size(), 5u);
  const std::vector<std::string> reasons = {"", "board not found", "", "image could not be decoded", ""};
  for (int i = 0; i < 5; ++i) EXPECT_EQ(rows[i].reason, reasons[i]) << i;

  // summary.json
  const nlohmann::json s = readJson(out + "/summary.json");
  EXPECT_EQ(s["backend"], "cslam");
  EXPECT_EQ(s["frames"], 5);
  EXPECT_EQ(s["tracked"], 2);
  EXPECT_EQ(s["lost"], 2);  // frames 1 and 3; frame 4 is waiting to start, not lost
  EXPECT_EQ(s["initialising"], 1);
  EXPECT_EQ(s["first_lost_frame"], 1);
  EXPECT_EQ(s["lost_reasons"]["board not found"], 1);
  EXPECT_EQ(s["lost_reasons"]["image could not be decoded"], 1);
  EXPECT_EQ(s["initialising_reasons"]["initialising"], 1);  // no reason given: its status
  EXPECT_EQ(s["sequence"], "seq");  // extra fields merged in
  // Back-end times of the four frames it processed: 5, 1, 3, 4 ms.
  const auto& ms = s["ms_per_frame"];
  EXPECT_DOUBLE_EQ(ms["median"].get<double>(), 3.5);
  EXPECT_DOUBLE_EQ(ms["mean"].get<double>(), 3.25);
  EXPECT_DOUBLE_EQ(ms["max"].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(ms["p99"].get<double>(), 5.0);
}

// A row is never cut at a buffer's size: a frame at 1e300 s keeps its own row, whole.
TEST(RunRecorder, RowsOfAHugeTimestampAreWhole) {
  test::TempDir dir;
  {
    RunRecorder recorder(dir.path(), "cslam");
    Frame frame = frameAt(0);
    frame.timestamp = 1e300;
    recorder.record(frame, tracked("board", SE3(), 54, 54), 5.0, 2.5, 1.5);
    recorder.record(frameAt(1), lost("board not found"), 1.0, 0.5, 1.25);
  }
  const auto rows = readLines(dir.file("frames.csv"));
  ASSERT_EQ(rows.size(), 3u);
  const auto row0 = splitCsv(rows[1]);
  ASSERT_EQ(row0.size(), 8u) << rows[1];
  EXPECT_EQ(std::stod(row0[1]), 1e300);
  EXPECT_EQ(row0[7], "54");
  EXPECT_EQ(splitCsv(rows[2])[2], "lost");
  const auto poses = readLines(dir.file("trajectory.txt"));
  ASSERT_EQ(poses.size(), 2u);  // the header and the one pose
  std::vector<double> v;
  ASSERT_TRUE(parseNumbers(poses[1], &v)) << poses[1];
  EXPECT_EQ(v.size(), 8u) << poses[1];
}

// Initialising rows wait for the next frame that is not; its late poses fill them in, in order.
TEST(RunRecorder, LatePosesFillTheInitialisingFramesInOrder) {
  test::TempDir dir;
  const SE3 T1 = SE3::fromRotvec(Vec3(0.1, 0.0, 0.0), Vec3(0.1, 0.0, -1.0));
  const SE3 T3 = SE3::fromRotvec(Vec3(0.2, 0.0, 0.0), Vec3(0.3, 0.0, -1.0));
  const SE3 T5 = SE3::fromRotvec(Vec3(0.3, 0.0, 0.0), Vec3(0.5, 0.0, -1.0));
  FrameResult initialising;
  initialising.status = TrackStatus::Initialising;
  initialising.reason = "gathering board views for self-calibration (1 of 8)";
  {
    RunRecorder recorder(dir.path(), "cslam");
    recorder.record(frameAt(0), initialising, 1.0, 0.5, 0.0);  // no board: stays initialising
    recorder.record(frameAt(1), initialising, 1.0, 0.5, 0.0);
    recorder.recordUndecodable(frameAt(2), 0.0);
    recorder.record(frameAt(3), initialising, 1.0, 0.5, 0.0);
    EXPECT_EQ(recorder.frames(), 4);
    EXPECT_EQ(readLines(dir.file("frames.csv")).size(), 1u);  // the header: the rows wait
    FrameResult calibrated = tracked("board", T5, 54, 54);
    calibrated.late_poses = {{1, "board", T1, 54}, {3, "board", T3, 54},
                             {4, "board", T3, 54}};  // 4 was not initialising: ignored
    recorder.record(frameAt(4), lost("board not found"), 1.0, 0.5, 0.0);
    recorder.record(frameAt(5), calibrated, 1.0, 0.5, 0.0);
    EXPECT_EQ(recorder.tracked(), 1);  // 4 was lost, so 0..3 were written before the late poses
    recorder.record(frameAt(6), initialising, 1.0, 0.5, 0.0);  // waits, then flushed by writeSummary
    recorder.writeSummary(nlohmann::json::object());
  }
  const auto lines = readLines(dir.file("frames.csv"));
  ASSERT_EQ(lines.size(), 8u);
  const std::vector<std::string> status = {"initialising", "initialising", "lost", "initialising",
                                           "lost", "board", "initialising"};
  for (int i = 0; i < 7; ++i) {
    EXPECT_EQ(std::stoi(splitCsv(lines[i + 1])[0]), i);
    EXPECT_EQ(splitCsv(lines[i + 1])[2], status[i]) << i;
  }

  // The same with the late poses arriving on the frame right after the initialising ones.
  test::TempDir dir2;
  {
    RunRecorder recorder(dir2.path(), "cslam");
    recorder.record(frameAt(0), initialising, 1.0, 0.5, 0.0);
    recorder.record(frameAt(1), initialising, 1.0, 0.5, 0.0);
    recorder.recordUndecodable(frameAt(2), 0.0);
    recorder.record(frameAt(3), initialising, 1.0, 0.5, 0.0);
    FrameResult calibrated = tracked("board", T5, 54, 54);
    calibrated.late_poses = {{1, "board", T1, 50}, {3, "board", T3, 52}};
    recorder.record(frameAt(4), calibrated, 1.0, 0.5, 0.0);
    EXPECT_EQ(recorder.tracked(), 3);
    recorder.writeSummary(nlohmann::json::object());
  }
  const auto rows = readLines(dir2.file("frames.csv"));
  ASSERT_EQ(rows.size(), 6u);
  const std::vector<std::string> status2 = {"initialising", "board", "lost", "board", "board"};
  for (int i = 0; i < 5; ++i) EXPECT_EQ(splitCsv(rows[i + 1])[2], status2[i]) << i;
  EXPECT_EQ(splitCsv(rows[2])[7], "50");  // measured
  const Trajectory t = readTrajectory(dir2.file("trajectory.txt"));
  ASSERT_EQ(t.size(), 3u);
  EXPECT_NEAR(t[0].timestamp, 10.1, 1e-9);
  EXPECT_NEAR(t[1].timestamp, 10.3, 1e-9);
  EXPECT_NEAR(t[2].timestamp, 10.4, 1e-9);
  EXPECT_LT((t[1].T_world_camera.t() - T3.t()).norm(), 1e-9);
  const nlohmann::json s = readJson(dir2.file("summary.json"));
  EXPECT_EQ(s["tracked"], 3);
  // An initialising frame is not lost: first_lost_frame is the undecodable one (a user looking it
  // up in frames.csv finds "lost" there).
  EXPECT_EQ(s["lost"], 1);
  EXPECT_EQ(s["initialising"], 1);
  EXPECT_EQ(s["first_lost_frame"], 2);
  EXPECT_EQ(s["lost_reasons"]["image could not be decoded"], 1);
  EXPECT_EQ(s["initialising_reasons"]["gathering board views for self-calibration (# of #)"], 1);
}

// The frame that brings the late poses may be unposed itself (a calibration accepted where the
// filter could not start): the earlier frames are posed all the same.
TEST(RunRecorder, LatePosesFromAnUnposedFrameAreKept) {
  test::TempDir dir;
  const SE3 T0 = SE3::fromRotvec(Vec3(0.1, 0.0, 0.0), Vec3(0.1, 0.0, -1.0));
  FrameResult initialising;
  initialising.status = TrackStatus::Initialising;
  {
    RunRecorder recorder(dir.path(), "hybrid");
    recorder.record(frameAt(0), initialising, 1.0, 0.5, 0.0);
    FrameResult calibrated_not_started = initialising;
    calibrated_not_started.late_poses = {{0, "board", T0, 54}};
    recorder.record(frameAt(1), calibrated_not_started, 1.0, 0.5, 0.0);
    recorder.writeSummary(nlohmann::json::object());
    EXPECT_EQ(recorder.tracked(), 1);
  }
  const auto lines = readLines(dir.file("frames.csv"));
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(splitCsv(lines[1])[2], "board");
  EXPECT_EQ(splitCsv(lines[2])[2], "initialising");
  EXPECT_EQ(readTrajectory(dir.file("trajectory.txt")).size(), 1u);
}

TEST(RunRecorder, AllTrackedHasNoFirstLostFrame) {
  test::TempDir dir;
  RunRecorder recorder(dir.path(), "monoslam");
  for (int i = 0; i < 3; ++i)
    recorder.record(frameAt(i), tracked("ekf", SE3(), 10, 9), 2.0 * (i + 1), 0.5 * 2.0 * (i + 1), 0.0);
  const nlohmann::json s = recorder.summary();
  EXPECT_EQ(s["frames"], 3);
  EXPECT_EQ(s["tracked"], 3);
  EXPECT_EQ(s["lost"], 0);
  EXPECT_TRUE(s["first_lost_frame"].is_null());
  EXPECT_DOUBLE_EQ(s["ms_per_frame"]["median"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(s["cpu_ms_per_frame"]["median"].get<double>(), 2.0);
}

// Per-stage CPU time: every call of a stage counted, its statistics in summary.json's `stages`.
TEST(RunRecorder, StagesAreSummarisedPerStage) {
  test::TempDir dir;
  RunRecorder recorder(dir.path(), "hybrid");
  for (int i = 0; i < 4; ++i) {
    FrameResult r = tracked("ekf", SE3(), 10, 9);
    r.stages = {{"predict", 0.1}, {"features", 1.0 + i}};
    if (i % 2 == 0) r.stages.push_back({"board", 2.0});
    recorder.record(frameAt(i), r, 3.0, 3.0, 0.0);
  }
  const nlohmann::json s = recorder.summary();
  EXPECT_EQ(s["stages"]["predict"]["calls"], 4);
  EXPECT_EQ(s["stages"]["board"]["calls"], 2);
  EXPECT_DOUBLE_EQ(s["stages"]["features"]["median"].get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(s["stages"]["features"]["max"].get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(s["stages"]["features"]["mean"].get<double>(), 2.5);
}

TEST(RunRecorder, WithoutPosesTheTrajectoryHoldsOnlyItsHeader) {
  test::TempDir dir;
  {
    RunRecorder recorder(dir.path(), "cslam");
    recorder.record(frameAt(0), lost("no board"), 1.0, 0.5, 0.0);
    recorder.record(frameAt(1), lost("no board"), 1.0, 0.5, 0.0);
    const nlohmann::json s = recorder.summary();
    EXPECT_EQ(s["tracked"], 0);
    EXPECT_EQ(s["first_lost_frame"], 0);
  }
  const auto lines = readLines(dir.file("trajectory.txt"));
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0][0], '#');
  EXPECT_THROW(readTrajectory(dir.file("trajectory.txt")), InputError);  // no made-up pose
  EXPECT_EQ(readLines(dir.file("frames.csv")).size(), 3u);
}

// A run interrupted before its first frame: its summary says 0 frames and its timings are null
// (JSON has no NaN), both in what writeSummary returns and in the file.
TEST(RunRecorder, NoFrameTimedLeavesTheTimingsNull) {
  test::TempDir dir;
  RunRecorder recorder(dir.path(), "cslam");
  const nlohmann::json returned = recorder.writeSummary({{"interrupted", true}});
  for (const nlohmann::json& s : {returned, readJson(dir.file("summary.json"))}) {
    EXPECT_EQ(s["frames"], 0);
    EXPECT_EQ(s["interrupted"], true);
    for (const char* timing : {"ms_per_frame", "cpu_ms_per_frame"})
      for (const char* statistic : {"median", "mean", "p99", "max"})
        EXPECT_TRUE(s[timing][statistic].is_null()) << timing << "." << statistic << ": " << s[timing];
  }
}



TEST(RunRecorder, UnwritableOutputIsAnInputError) {
  test::TempDir dir;
  test::writeText(dir.file("file"), "x");
  EXPECT_THROW(RunRecorder(dir.file("file/run"), "cslam"), InputError);  // a file in the way
}

TEST(RunRecorder, LostReasonsAreCountedByCategoryNotByTheirNumbers) {
  EXPECT_EQ(reasonCategory("too few two-view inliers (12 of 140)"), "too few two-view inliers (# of #)");
  EXPECT_EQ(reasonCategory("diverged: camera position std 1.25 m"), "diverged: camera position std # m");
  EXPECT_EQ(reasonCategory("parallax 1e-3 px, step -0.5"), "parallax # px, step #");
  EXPECT_EQ(reasonCategory("no board"), "no board");
}

// A reason is free text: commas, quotes and a line break survive the CSV (quoted, the break made
// a space), and a frames.csv written before the reason column is still read.
TEST(RunRecorder, ReasonsWithCommasAndQuotesAndOldFilesRead) {
  test::TempDir dir;
  const std::string reason = "too few measured (2, need 3) \"ekf\"\nfor 3 frames";
  {
    RunRecorder recorder(dir.path(), "monoslam");
    recorder.record(frameAt(0), lost(reason), 1.0, 0.5, 0.0);
    FrameResult noted = tracked("ekf", SE3(), 10, 0);
    noted.reason = "no feature matched: prediction only";
    recorder.record(frameAt(1), noted, 1.0, 0.5, 0.0);
  }
  const std::vector<FrameRow> rows = readFramesCsv(dir.file("frames.csv"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].reason, "too few measured (2, need 3) \"ekf\" for 3 frames");
  EXPECT_EQ(rows[0].measured, 0);
  EXPECT_EQ(rows[1].reason, "no feature matched: prediction only");
  EXPECT_EQ(rows[1].source, "ekf");

  const std::string old_file = dir.file("old.csv");
  std::ofstream(old_file) << "frame,timestamp,status,ms,cpu_ms,decode_ms,features,measured\n"
                          << "0,1.000000,lost,1.0,0.5,0.0,0,0\r\n";
  const std::vector<FrameRow> old_rows = readFramesCsv(old_file);
  ASSERT_EQ(old_rows.size(), 1u);
  EXPECT_EQ(old_rows[0].status, TrackStatus::Lost);
  EXPECT_TRUE(old_rows[0].reason.empty());

  const std::string open_quote = dir.file("open.csv");
  std::ofstream(open_quote) << framesCsvHeader() << "\n0,1.000000,lost,1.0,0.5,0.0,0,0,\"cut\n";
  EXPECT_THROW(readFramesCsv(open_quote), InputError);
}

}  // namespace
}  // namespace slamcmp
