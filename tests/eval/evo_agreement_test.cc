// slamcmp eval against evo's own figures (evo_reference.json, made by make_evo_reference.py;
// see README.md) on the shared TUM, EuRoC and KITTI trajectories: 1e-6 relative.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <iostream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/trajectory.h"
#include "eval/metrics/trajectory_metrics.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

double worst_relative = 0.0;  // reported at the end, for the record

// 1e-6 relative; the 1e-12 floor only matters for evo values that are exactly 0 (the first KITTI
// pose of both files is the identity).
void expectAgrees(double ours, double evo, const std::string& what) {
  EXPECT_LE(std::abs(ours - evo), 1e-6 * std::abs(evo) + 1e-12)
      << what << ": slamcmp " << ours << ", evo " << evo;
  if (evo != 0.0) worst_relative = std::max(worst_relative, std::abs(ours - evo) / std::abs(evo));
}

void expectStatisticsAgree(const Statistics& s, const nlohmann::json& evo,
                           const std::string& what) {
  expectAgrees(s.rmse, evo["rmse"], what + " rmse");
  expectAgrees(s.mean, evo["mean"], what + " mean");
  expectAgrees(s.median, evo["median"], what + " median");
  expectAgrees(s.std, evo["std"], what + " std");
  expectAgrees(s.min, evo["min"], what + " min");
  expectAgrees(s.max, evo["max"], what + " max");
}

TEST(EvoAgreement, SharedTrajectories) {
  SLAMCMP_REQUIRE_SHARED(shared);
  std::ifstream in(std::string(SLAMCMP_SOURCE_DIR) + "/tests/eval/evo_reference.json");
  ASSERT_TRUE(in.good());
  const nlohmann::json reference = nlohmann::json::parse(in);
  ASSERT_GE(reference["cases"].size(), 10u);
  const std::string folder = shared + "/trajectories_evo/";
  for (const auto& c : reference["cases"]) {
    const std::string what = c["name"].get<std::string>() + " " + c["align"].get<std::string>();
    SCOPED_TRACE(what);
    const Trajectory gt = readTrajectory(folder + c["groundtruth"].get<std::string>());
    const Trajectory est = readTrajectory(folder + c["estimate"].get<std::string>());
    EvalOptions options;
    options.align = c["align"];
    options.max_diff = c["max_diff"];
    options.delta = c["rpe"]["delta_frames"];
    const TrajectoryEvaluation e = evaluateTrajectory(gt, est, options);

    EXPECT_EQ(e.pairs.size(), c["matched"].get<size_t>());
    EXPECT_EQ(e.rpe_trans.size(), c["rpe"]["pairs"].get<size_t>());
    expectAgrees(e.T_gt_estimate.scale, c["scale"], what + " scale");
    expectStatisticsAgree(e.ate_trans_stats, c["ate"]["trans"], what + " ATE trans");
    expectStatisticsAgree(e.ate_rot_deg_stats, c["ate"]["rot_deg"], what + " ATE rot");
    expectStatisticsAgree(e.rpe_trans_stats, c["rpe"]["trans"], what + " RPE trans");
    expectStatisticsAgree(e.rpe_rot_deg_stats, c["rpe"]["rot_deg"], what + " RPE rot");
    const auto& axes = c["ate"]["trans_axis_rmse"];
    expectAgrees(e.ate_axis_rmse.x(), axes["x"], what + " ATE x rmse");
    expectAgrees(e.ate_axis_rmse.y(), axes["y"], what + " ATE y rmse");
    expectAgrees(e.ate_axis_rmse.z(), axes["z"], what + " ATE z rmse");
  }
  std::cout << "largest relative difference from evo: " << worst_relative << "\n";
}

}  // namespace
}  // namespace slamcmp
