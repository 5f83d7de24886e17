// Trajectory readers on evo's test files (TUM, EuRoC, KITTI), every malformed case naming
// file:line, and the TUM writer.
#include "core/trajectory.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

// The data lines of a file, split at spaces and commas, counted independently of the reader.
std::vector<std::vector<std::string>> dataLines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    for (char& c : line)
      if (c == ',') c = ' ';
    std::istringstream ss(line);
    std::vector<std::string> fields;
    for (std::string f; ss >> f;) fields.push_back(f);
    out.push_back(fields);
  }
  return out;
}

double num(const std::string& s) { return std::strtod(s.c_str(), nullptr); }

// Same rotation as the quaternion (w, x, y, z) of the file, up to its sign.
void expectQuat(const SE3& T, double w, double x, double y, double z) {
  const Quat q = Quat(w, x, y, z).normalized();
  EXPECT_NEAR(std::abs(T.quat().dot(q)), 1.0, 1e-12);
}

void expectPoseMatchesLine(const StampedPose& pose, const std::vector<std::string>& f,
                           TrajectoryFormat format, double kitti_time) {
  switch (format) {
    case TrajectoryFormat::Tum:
      ASSERT_EQ(f.size(), 8u);
      EXPECT_EQ(pose.timestamp, num(f[0]));
      EXPECT_EQ(pose.T_world_camera.t(), Vec3(num(f[1]), num(f[2]), num(f[3])));
      expectQuat(pose.T_world_camera, num(f[7]), num(f[4]), num(f[5]), num(f[6]));
      break;
    case TrajectoryFormat::Euroc:
      ASSERT_GE(f.size(), 8u);
      EXPECT_EQ(pose.timestamp, num(f[0]) / 1e9);  // correctly rounded, as evo
      EXPECT_EQ(pose.T_world_camera.t(), Vec3(num(f[1]), num(f[2]), num(f[3])));
      expectQuat(pose.T_world_camera, num(f[4]), num(f[5]), num(f[6]), num(f[7]));
      break;
    default: {
      ASSERT_EQ(f.size(), 12u);
      EXPECT_EQ(pose.timestamp, kitti_time);
      EXPECT_EQ(pose.T_world_camera.t(), Vec3(num(f[3]), num(f[7]), num(f[11])));
      // The 3x3 part is kept as written when orthonormal to 1e-5 (as evo), else projected onto SO(3).
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          EXPECT_NEAR(pose.T_world_camera.R()(r, c), num(f[4 * r + c]), 2e-6) << r << "," << c;
      break;
    }
  }
}

struct EvoFile {
  std::string file;
  TrajectoryFormat format;  // what Auto must find
  std::string kitti_times;  // "" for none
};

// gtest prints the parameter by its name.
void PrintTo(const EvoFile& c, std::ostream* os) {
  *os << c.file << (c.kitti_times.empty() ? "" : " with " + c.kitti_times);
}

class EvoTrajectories : public ::testing::TestWithParam<EvoFile> {};

TEST_P(EvoTrajectories, ReadsEveryPoseExactly) {
  SLAMCMP_REQUIRE_SHARED(data);
  const EvoFile& evo = GetParam();
  const std::string dir = data + "/trajectories_evo/";
  const std::string times = evo.kitti_times.empty() ? "" : dir + evo.kitti_times;
  const Trajectory t = readTrajectory(dir + evo.file, TrajectoryFormat::Auto, times);
  const auto lines = dataLines(dir + evo.file);
  ASSERT_EQ(t.size(), lines.size());
  std::vector<double> stamps;
  if (!times.empty())
    for (const auto& l : dataLines(times)) stamps.push_back(num(l[0]));
  const auto kittiTime = [&](size_t i) {
    return stamps.empty() ? static_cast<double>(i) : stamps[i];
  };
  expectPoseMatchesLine(t.front(), lines.front(), evo.format, kittiTime(0));
  expectPoseMatchesLine(t.back(), lines.back(), evo.format, kittiTime(t.size() - 1));
  const size_t mid = t.size() / 2;
  expectPoseMatchesLine(t[mid], lines[mid], evo.format, kittiTime(mid));
  // The explicit format reads the same.
  const Trajectory explicit_format = readTrajectory(dir + evo.file, evo.format, times);
  ASSERT_EQ(explicit_format.size(), t.size());
  EXPECT_EQ(explicit_format.back().T_world_camera.matrix(), t.back().T_world_camera.matrix());
}

INSTANTIATE_TEST_SUITE_P(
    Files, EvoTrajectories,
    ::testing::Values(EvoFile{"freiburg1_xyz-groundtruth.txt", TrajectoryFormat::Tum, ""},
                      EvoFile{"freiburg1_xyz-rgbdslam.txt", TrajectoryFormat::Tum, ""},
                      EvoFile{"freiburg1_xyz-ORB_kf_mono.txt", TrajectoryFormat::Tum, ""},
                      EvoFile{"fr2_desk_groundtruth.txt", TrajectoryFormat::Tum, ""},
                      EvoFile{"fr2_desk_ORB.txt", TrajectoryFormat::Tum, ""},
                      EvoFile{"fr2_desk_ORB_kf_mono.txt", TrajectoryFormat::Tum, ""},
                      EvoFile{"V102.txt", TrajectoryFormat::Tum, ""},
                      EvoFile{"V102_groundtruth.csv", TrajectoryFormat::Euroc, ""},
                      EvoFile{"KITTI_00_gt.txt", TrajectoryFormat::Kitti, ""},
                      EvoFile{"KITTI_00_gt.txt", TrajectoryFormat::Kitti, "KITTI_00_gt_times.txt"},
                      EvoFile{"KITTI_00_ORB.txt", TrajectoryFormat::Kitti, "KITTI_00_gt_times.txt"},
                      EvoFile{"KITTI_00_SPTAM.txt", TrajectoryFormat::Kitti, ""}),
    [](const auto& info) {
      std::string name = info.param.file + (info.param.kitti_times.empty() ? "" : "_with_times");
      for (char& c : name)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
      return name;
    });

struct BadTrajectory {
  std::string name;
  std::string file;     // file name in the temporary folder (its extension picks EuRoC)
  std::string content;  // "" with `file` absent: a missing file
  std::string where;    // what the message must name after the folder: "traj.txt:3"
  std::string times;    // KITTI times file content ("" for none)
};

void PrintTo(const BadTrajectory& c, std::ostream* os) { *os << c.name; }

class BadTrajectories : public ::testing::TestWithParam<BadTrajectory> {};

TEST_P(BadTrajectories, ThrowsNamingFileAndLine) {
  const BadTrajectory& bad = GetParam();
  test::TempDir dir;
  if (!bad.content.empty()) test::writeText(dir.file(bad.file), bad.content);
  std::string times;
  if (!bad.times.empty()) {
    times = dir.file("times.txt");
    test::writeText(times, bad.times);
  }
  try {
    readTrajectory(dir.file(bad.file), TrajectoryFormat::Auto, times);
    FAIL() << "accepted " << bad.name;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(dir.file(bad.where)), std::string::npos) << message;
  }
}

const char* kTumHeader = "# timestamp tx ty tz qx qy qz qw\n";
const char* kKittiLine = "1 0 0 0.5 0 1 0 0 0 0 1 2\n";

INSTANTIATE_TEST_SUITE_P(
    Cases, BadTrajectories,
    ::testing::Values(
        BadTrajectory{"missing_file", "none.txt", "", "none.txt", ""},
        BadTrajectory{"empty_file", "traj.txt", "\n", "traj.txt", ""},
        BadTrajectory{"only_comments", "traj.txt", "# nothing\n", "traj.txt", ""},
        BadTrajectory{"tum_wrong_field_count", "traj.txt",
                      std::string(kTumHeader) + "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 1\n",
                      "traj.txt:3", ""},
        BadTrajectory{"first_line_field_count", "traj.txt", "1.0 0 0 0 0 0 1\n", "traj.txt:1", ""},
        BadTrajectory{"not_a_number", "traj.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 x 0 0 0 0 1\n",
                      "traj.txt:2", ""},
        BadTrajectory{"nan", "traj.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 nan 0 0 0 0 1\n", "traj.txt:2",
                      ""},
        BadTrajectory{"infinity", "traj.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 inf 0 0 0 1\n",
                      "traj.txt:2", ""},
        BadTrajectory{"non_unit_quaternion", "traj.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 2\n",
                      "traj.txt:2", ""},
        BadTrajectory{"zero_quaternion", "traj.txt", "1.0 0 0 0 0 0 0 0\n", "traj.txt:1", ""},
        BadTrajectory{"decreasing_timestamp", "traj.txt", "1.0 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n",
                      "traj.txt:2", ""},
        BadTrajectory{
            "decreasing_after_duplicate", "traj.txt",
            "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n\n2.0 1 0 0 0 0 0 1\n1.9 0 0 0 0 0 0 1\n",
            "traj.txt:5", ""},
        BadTrajectory{"euroc_too_few_fields", "gt.csv",
                      "#timestamp, x, y, z, qw, qx, qy, qz\n100,0,0,0,1,0,0,0\n200,0,0,0,1,0\n",
                      "gt.csv:3", ""},
        BadTrajectory{"euroc_non_unit_quaternion", "gt.csv",
                      "100,0,0,0,1,0,0,0\n200,0,0,0,0.5,0,0,0\n", "gt.csv:2", ""},
        BadTrajectory{"kitti_not_a_rotation", "kitti.txt",
                      std::string(kKittiLine) + "2 0 0 0 0 1 0 0 0 0 1 2\n", "kitti.txt:2", ""},
        BadTrajectory{"kitti_reflection", "kitti.txt", "-1 0 0 0 0 1 0 0 0 0 1 0\n", "kitti.txt:1",
                      ""},
        BadTrajectory{"kitti_fewer_times", "kitti.txt",
                      std::string(kKittiLine) + kKittiLine + kKittiLine, "times.txt", "0.0\n0.1\n"},
        BadTrajectory{"kitti_more_times", "kitti.txt", std::string(kKittiLine) + kKittiLine,
                      "times.txt", "0.0\n0.1\n0.2\n"},
        BadTrajectory{"kitti_times_going_back", "kitti.txt",
                      std::string(kKittiLine) + kKittiLine, "times.txt:2", "0.2\n0.1\n"},
        BadTrajectory{"huge_timestamp", "traj.txt", "1.0 0 0 0 0 0 0 1\n2e300 0 0 0 0 0 0 1\n", "traj.txt:2", ""},
        BadTrajectory{"huge_negative_timestamp", "traj.txt", "-2e300 0 0 0 0 0 0 1\n", "traj.txt:1", ""},
        BadTrajectory{"euroc_huge_timestamp", "gt.csv", "100,0,0,0,1,0,0,0\n1e30,0,0,0,1,0,0,0\n", "gt.csv:2", ""},
        BadTrajectory{"kitti_huge_time", "kitti.txt", std::string(kKittiLine) + kKittiLine, "times.txt:2",
                      "0.0\n1e300\n"},
        // Positions whose squares overflow made ATE inf and its statistics NaN, exit 0.
        BadTrajectory{"huge_position", "traj.txt", "1.0 0 0 0 0 0 0 1\n2.0 0 1e200 0 0 0 0 1\n", "traj.txt:2", ""},
        BadTrajectory{"kitti_huge_position", "kitti.txt", std::string(kKittiLine) + "1 0 0 -2e101 0 1 0 0 0 0 1 2\n",
                      "kitti.txt:2", ""}),
    [](const auto& info) { return info.param.name; });

// Published ground truth repeats a timestamp now and then (TUM fr2_desk, evo's V1_02 estimate):
// both poses are kept in file order, as evo keeps them.
TEST(Trajectory, RepeatedTimestampsAreKeptInOrder) {
  test::TempDir dir;
  const std::string path = dir.file("traj.txt");
  test::writeText(path,
                  "1.0 0 0 0 0 0 0 1\n2.0 0 0 0 0 0 0 1\n2.0 1 0 0 0 0 0 1\n3.0 2 0 0 0 0 0 1\n");
  const Trajectory t = readTrajectory(path);
  ASSERT_EQ(t.size(), 4u);
  EXPECT_EQ(t[1].timestamp, 2.0);
  EXPECT_EQ(t[2].timestamp, 2.0);
  EXPECT_EQ(t[1].T_world_camera.t().x(), 0.0);
  EXPECT_EQ(t[2].T_world_camera.t().x(), 1.0);
}

// A TUM file saved as .csv (spaces, not EuRoC's commas) is read as TUM: read as EuRoC its seconds
// were taken for nanoseconds, and poses seconds apart paired within any --max-diff.
TEST(Trajectory, ACsvIsEurocOnlyWhenCommaSeparated) {
  test::TempDir dir;
  const std::string tum_csv = dir.file("tum.csv");
  test::writeText(tum_csv, "# timestamp tx ty tz qx qy qz qw\n105.95 1 2 3 0 0 0 1\n106.05 1 2 3 0 0 0 1\n");
  EXPECT_EQ(detectTrajectoryFormat(tum_csv), TrajectoryFormat::Tum);
  const Trajectory t = readTrajectory(tum_csv);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_EQ(t[0].timestamp, 105.95);
  const std::string euroc = dir.file("gt.csv");
  test::writeText(euroc, "#timestamp,p_x,p_y,p_z,q_w,q_x,q_y,q_z\n1403715572212143183,1,2,3,1,0,0,0\n");
  EXPECT_EQ(detectTrajectoryFormat(euroc), TrajectoryFormat::Euroc);
  EXPECT_EQ(readTrajectory(euroc).front().timestamp, 1403715572212143183.0 / 1e9);
}

// Seconds since 1970 are about 1.7e9; nanoseconds (EuRoC's unit) in a TUM file are refused, saying so.
TEST(Trajectory, NanosecondsInATumFileAreRefusedSayingSo) {
  test::TempDir dir;
  const std::string path = dir.file("traj.txt");
  test::writeText(path, "1403715572212143183 0 0 0 0 0 0 1\n");
  try {
    readTrajectory(path);
    FAIL() << "accepted nanoseconds as seconds";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path + ":1: timestamp 1.40372e+18 is not plausible as seconds"), std::string::npos)
        << message;
    EXPECT_NE(message.find("looks like nanoseconds (1.40372e+09 s)"), std::string::npos) << message;
  }
}

// A line is never cut at a buffer's size, however many digits a value prints with.
TEST(Trajectory, TumLineOfAHugeTimestampIsWhole) {
  const std::string line = formatTumLine({1e300, SE3(Quat(0.5, 0.5, 0.5, 0.5), Vec3(1, 2, 3))});
  EXPECT_GT(line.size(), 300u);
  std::vector<double> v;
  ASSERT_TRUE(parseNumbers(line, &v)) << line;
  ASSERT_EQ(v.size(), 8u) << line;
  EXPECT_EQ(v[0], 1e300);
  EXPECT_EQ(v[7], 0.5);  // qw, the last field
}

TEST(Trajectory, WriteTumThenReadRoundTrip) {
  test::TempDir dir;
  Trajectory t;
  for (int i = 0; i < 50; ++i) {
    const double a = 0.07 * i;
    StampedPose p;
    p.timestamp = 1305031102.160407 + 0.033 * i;
    p.T_world_camera = SE3::fromRotvec(Vec3(std::sin(a), 0.3 * a, -0.5 + 0.06 * i),
                                       Vec3(1.5 * std::cos(a), -0.25 * i, 0.123456789 * i));
    t.push_back(p);
  }
  const std::string path = dir.file("trajectory.txt");
  writeTumTrajectory(path, t);
  const Trajectory back = readTrajectory(path);
  ASSERT_EQ(back.size(), t.size());
  for (size_t i = 0; i < t.size(); ++i) {
    EXPECT_NEAR(back[i].timestamp, t[i].timestamp, 1e-6);  // microseconds are written
    EXPECT_LT((back[i].T_world_camera.t() - t[i].T_world_camera.t()).norm(), 1e-8);
    EXPECT_LT(rotationAngle(back[i].T_world_camera.R().transpose() * t[i].T_world_camera.R()),
              1e-8);
  }
  // The header is a comment TUM tools skip; every other line has 8 fields.
  const auto lines = dataLines(path);
  ASSERT_EQ(lines.size(), t.size());
  for (const auto& l : lines) EXPECT_EQ(l.size(), 8u);
}

TEST(Trajectory, ParseFormatNames) {
  EXPECT_EQ(parseTrajectoryFormat("tum"), TrajectoryFormat::Tum);
  EXPECT_EQ(parseTrajectoryFormat("euroc"), TrajectoryFormat::Euroc);
  EXPECT_EQ(parseTrajectoryFormat("kitti"), TrajectoryFormat::Kitti);
  EXPECT_EQ(parseTrajectoryFormat("auto"), TrajectoryFormat::Auto);
  EXPECT_THROW(parseTrajectoryFormat("bag"), InputError);
  std::vector<double> v;
  EXPECT_TRUE(parseNumbers("1.5, -2e3\t7 ", &v));
  EXPECT_EQ(v, (std::vector<double>{1.5, -2000.0, 7.0}));
  EXPECT_FALSE(parseNumbers("1.5 2x", &v));
}

}  // namespace
}  // namespace slamcmp
