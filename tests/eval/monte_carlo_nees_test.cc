// Bar-Shalom's Monte Carlo NEES test (eval/metrics/monte_carlo_nees.h) on NEES drawn from the
// chi-square distribution a consistent filter gives (the sum of 6 squared standard normals), and
// from filters over- and underconfident by a factor of 2; and nees.csv, which carries a run's
// per-frame NEES to compare, read back exactly and refused when a value is not a number.
#include "eval/metrics/monte_carlo_nees.h"

#include <cmath>
#include <fstream>
#include <random>

#include <gtest/gtest.h>

#include "core/error.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

// `trials` runs of `frames` frames at 10 Hz; each frame's NEES chi-square with 6 dof, times `factor`.
std::vector<std::vector<TimedNees>> drawRuns(int trials, int frames, double factor, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  std::vector<std::vector<TimedNees>> runs(trials);
  for (auto& run : runs)
    for (int k = 0; k < frames; ++k) {
      double nees = 0;
      for (int d = 0; d < 6; ++d) nees += std::pow(normal(rng), 2);
      run.push_back({0.1 * k, factor * nees});
    }
  return runs;
}

TEST(MonteCarloNees, AConsistentFilterIsInsideOnNinetyFivePercentOfTheFrames) {
  // 1000 frames: the share inside is binomial with std 0.7 %.
  double width = INFINITY;
  for (int trials : {2, 10, 50}) {
    const auto mc = monteCarloNees(drawRuns(trials, 1000, 1.0, 7 + trials));
    ASSERT_TRUE(mc.has_value());
    EXPECT_EQ(mc->steps(), 1000);
    EXPECT_EQ(mc->inside + mc->above + mc->below, 1000);
    EXPECT_NEAR(mc->inside / 1000.0, 0.95, 0.025) << trials << " trials";
    EXPECT_NEAR(mc->above / 1000.0, 0.025, 0.015) << trials << " trials";
    EXPECT_NEAR(mc->mean, 6.0, 0.2) << trials << " trials";
    // The interval narrows as trials are added: chi-square(6M) / M (2 trials: 2.2 to 11.7).
    EXPECT_LT(mc->upper.front() - mc->lower.front(), width);
    width = mc->upper.front() - mc->lower.front();
    EXPECT_EQ(mc->trials.front(), trials);
  }
}

TEST(MonteCarloNees, OverAndUnderconfidenceShowAboveAndBelow) {
  const auto over = monteCarloNees(drawRuns(20, 300, 2.0, 1));
  const auto under = monteCarloNees(drawRuns(20, 300, 0.5, 2));
  ASSERT_TRUE(over && under);
  EXPECT_GT(over->above, 0.95 * 300);
  EXPECT_GT(under->below, 0.95 * 300);
  // With 2 trials the interval is wide (2.2 to 11.7, for a mean of 6): half the frames of a filter twice
  // too confident still fall inside; it takes trials to see it.
  const auto few = monteCarloNees(drawRuns(2, 300, 2.0, 3));
  ASSERT_TRUE(few);
  EXPECT_GT(few->inside, 0.3 * 300);
  EXPECT_LT(few->inside, 0.8 * 300);
}

TEST(MonteCarloNees, FramesAreMatchedByTimestampAndNeedTwoTrials) {
  // A run that scored 0.2 twice counts once there (its last).
  std::vector<std::vector<TimedNees>> runs{{{0.0, 4}, {0.1, 6}, {0.2, 100}, {0.2, 8}}, {{0.1000004, 10}, {0.2, 2}},
                                           {{0.3, 5}}};
  const auto mc = monteCarloNees(runs);
  ASSERT_TRUE(mc.has_value());
  ASSERT_EQ(mc->steps(), 2);  // 0.0 and 0.3 were scored by one trial only
  EXPECT_DOUBLE_EQ(mc->timestamps[0], 0.1);
  EXPECT_DOUBLE_EQ(mc->anees[0], 8.0);
  EXPECT_DOUBLE_EQ(mc->anees[1], 5.0);
  EXPECT_EQ(mc->trials[0], 2);
  EXPECT_EQ(mc->trials[1], 2);
  EXPECT_FALSE(monteCarloNees({{{0.0, 6}}, {{0.1, 6}}}).has_value());
  EXPECT_FALSE(monteCarloNees({}).has_value());
}

TEST(NeesCsv, RoundTripsExactlyAndRefusesWhatIsNotANumber) {
  test::TempDir dir;
  NeesResult written;
  written.per_frame = {{0.1, 6.123456789012345}, {1e9 + 0.033333, 1e-12}, {2.5, 0}};
  written.per_frame_parts = {{3.5, 2.25}, {1e-13, 1e-12}, {0, 0}};
  const std::vector<TimedNees>& rows = written.per_frame;
  writeNeesCsv(dir.file("nees.csv"), written);
  std::string header;
  std::getline(std::ifstream(dir.file("nees.csv")) >> std::ws, header);
  EXPECT_EQ(header, "timestamp,nees,position,orientation");
  const std::vector<TimedNees> back = readNeesCsv(dir.file("nees.csv"));
  ASSERT_EQ(back.size(), rows.size());
  for (size_t k = 0; k < rows.size(); ++k) {
    EXPECT_EQ(back[k].timestamp, rows[k].timestamp);
    EXPECT_EQ(back[k].nees, rows[k].nees);
  }
  const auto refused = [&](const std::string& text, const std::string& message) {
    std::ofstream(dir.file("bad.csv")) << text;
    try {
      readNeesCsv(dir.file("bad.csv"));
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  refused("timestamp,nees\n0.1,nan\n", "bad.csv:2: nees is not a finite number");
  refused("timestamp,nees\n0.1,6\nx,6\n", "bad.csv:3: timestamp is not a finite number");
  refused("timestamp,nees\n0.1,-1\n", "bad.csv:2: nees is negative");
  refused("timestamp,nees\n0.1 6\n", "bad.csv:2: expected timestamp,nees");
  refused("t,n\n", "bad.csv:1: header is not timestamp,nees");
  refused("timestamp,nees\n0.1,6abc\n", "bad.csv:2: nees is not a finite number");
  refused("timestamp,nees\n0.1,6,3\n", "bad.csv:2: expected timestamp,nees");
  refused("timestamp,nees,position,orientation\n0.1,6,3\n", "bad.csv:2: expected timestamp,nees,position,orientation");
  refused("timestamp,nees,position,orientation\n0.1,6,3,-1\n", "bad.csv:2: orientation is negative");
  refused("timestamp,nees,position,orientation\n0.1,6,inf,1\n", "bad.csv:2: position is not a finite number");
  // A file of an earlier version (no parts) is still read.
  std::ofstream(dir.file("earlier.csv")) << "timestamp,nees\n0.1,6\n0.2,5\n";
  const std::vector<TimedNees> earlier = readNeesCsv(dir.file("earlier.csv"));
  ASSERT_EQ(earlier.size(), 2u);
  EXPECT_EQ(earlier[1].nees, 5);
  // Windows line ends and a blank last line are read as they are meant.
  std::ofstream(dir.file("crlf.csv")) << "timestamp,nees\r\n0.1,6\r\n\n";
  ASSERT_EQ(readNeesCsv(dir.file("crlf.csv")).size(), 1u);
}

}  // namespace
}  // namespace slamcmp
