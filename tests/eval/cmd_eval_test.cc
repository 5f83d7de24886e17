// `slamcmp eval` through the real binary: the --json contract and the bad-input contract (exit
// code 2, one stderr line).
#include <algorithm>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/test_util.h"

namespace slamcmp {
namespace {

using test::runSlamcmp;
using test::TempDir;
using test::writeText;

int lineCount(const std::string& s) {
  return static_cast<int>(std::count(s.begin(), s.end(), '\n'));
}

// Five poses on a parabola at 10 Hz; the estimate is 0.1 m off in z, with timestamps in `unit`
// seconds.
void writePair(const TempDir& tmp, double unit) {
  std::string gt, est;
  for (int i = 0; i < 5; ++i) {
    const double t = 100.0 + 0.1 * i;
    char line[128];
    std::snprintf(line, sizeof line, "%.6f %d %d 0 0 0 0 1\n", t, i, i * i);
    gt += line;
    std::snprintf(line, sizeof line, "%.6f %d %d 0.1 0 0 0 1\n", t / unit, i, i * i);
    est += line;
  }
  writeText(tmp.file("gt.txt"), "# timestamp tx ty tz qx qy qz qw\n" + gt);
  writeText(tmp.file("est.txt"), est);
}

TEST(CmdEval, JsonHasTheSpecKeys) {
  TempDir tmp;
  writePair(tmp, 1.0);
  const auto r = runSlamcmp("eval --groundtruth " + tmp.file("gt.txt") + " --estimate " +
                            tmp.file("est.txt") + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["matched"], 5);
  EXPECT_EQ(j["align"], "none");
  EXPECT_EQ(j["scale"], 1.0);
  EXPECT_EQ(j["rpe"]["delta_frames"], 1);
  for (const auto* block :
       {&j["ate"]["trans"], &j["ate"]["rot_deg"], &j["rpe"]["trans"], &j["rpe"]["rot_deg"]})
    for (const char* key : {"rmse", "mean", "median", "std", "min", "max"})
      EXPECT_TRUE(block->contains(key)) << key;
  EXPECT_NEAR(j["ate"]["trans"]["rmse"].get<double>(), 0.1, 1e-9);
  EXPECT_NEAR(j["ate"]["trans_axis_rmse"]["z"].get<double>(), 0.1, 1e-9);
  EXPECT_NEAR(j["rpe"]["trans"]["max"].get<double>(), 0.0, 1e-9);
}

TEST(CmdEval, TableByDefault) {
  TempDir tmp;
  writePair(tmp, 1.0);
  const auto r = runSlamcmp("eval --groundtruth " + tmp.file("gt.txt") + " --estimate " +
                            tmp.file("est.txt") + " --align se3 --delta 2");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("ATE trans (m)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("RPE rot (deg)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("alignment se3"), std::string::npos) << r.out;
}

TEST(CmdEval, MissingFileIsBadInput) {
  TempDir tmp;
  writePair(tmp, 1.0);
  const auto r = runSlamcmp("eval --groundtruth " + tmp.file("nope.txt") + " --estimate " +
                            tmp.file("est.txt"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("nope.txt"), std::string::npos) << r.err;
}

TEST(CmdEval, NoAssociationIsBadInputWithAHint) {
  TempDir tmp;
  writePair(tmp, 1e-9);  // estimate stamped in ns
  const auto r = runSlamcmp("eval --groundtruth " + tmp.file("gt.txt") + " --estimate " +
                            tmp.file("est.txt") + " --json");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("ns"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("est.txt"), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(CmdEval, BadAlignIsBadInput) {
  TempDir tmp;
  writePair(tmp, 1.0);
  const auto r = runSlamcmp("eval --groundtruth " + tmp.file("gt.txt") + " --estimate " +
                            tmp.file("est.txt") + " --align affine");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(lineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("--align"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace slamcmp
