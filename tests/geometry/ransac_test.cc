// geometry/ransac.h: the adaptive number of trials and the inlier set, on planted data (a line
// with planted outliers, and the eight-point essential matrix with planted mismatches).
#include "geometry/ransac.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "geometry/essential_eight_point.h"
#include "geometry/two_view_estimators.h"
#include "geometry/two_view_motion.h"

namespace slamcmp {
namespace {

// A 2D line a x + b y + c = 0 (a^2 + b^2 = 1) through two points; the residual is the distance.
struct LineEstimator {
  using Model = Vec3;
  static constexpr int kMinSamples = 2;
  std::vector<Vec2> points;

  int numData() const { return static_cast<int>(points.size()); }
  std::vector<Model> estimate(const std::vector<int>& sample) const {
    const Vec2& p = points[sample[0]];
    const Vec2& q = points[sample[1]];
    const Vec2 d = q - p;
    if (d.norm() < 1e-12) return {};
    const Vec2 normal = Vec2(-d.y(), d.x()).normalized();
    return {Vec3(normal.x(), normal.y(), -normal.dot(p))};
  }
  double squaredError(const Model& line, int i) const {
    const double e = line.x() * points[i].x() + line.y() * points[i].y() + line.z();
    return e * e;
  }
};

struct PlantedLine {
  LineEstimator estimator;
  std::vector<char> inlier;  // planted
};

// `inliers` points exactly on y = 0.5 x + 1 and `outliers` at least 0.5 (50 thresholds of 0.01)
// off it, in a 10 x 10 box, shuffled.
PlantedLine plantLine(int inliers, int outliers, int seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-5, 5);
  PlantedLine planted;
  std::vector<std::pair<Vec2, char>> all;
  for (int i = 0; i < inliers; ++i) {
    const double x = u(rng);
    all.push_back({Vec2(x, 0.5 * x + 1), 1});
  }
  const double norm = std::sqrt(1.25);
  while (static_cast<int>(all.size()) < inliers + outliers) {
    const Vec2 p(u(rng), u(rng));
    if (std::abs(0.5 * p.x() - p.y() + 1) / norm > 0.5) all.push_back({p, 0});
  }
  std::shuffle(all.begin(), all.end(), rng);
  for (const auto& [p, is_inlier] : all) {
    planted.estimator.points.push_back(p);
    planted.inlier.push_back(is_inlier);
  }
  return planted;
}

struct TrialCase {
  int inliers, outliers;
  double confidence;
  int min_iterations, max_iterations;
  int expected;  // the clamped N = ceil(log(1 - p) / log(1 - w^2)), worked out by hand
};

std::string trialName(const ::testing::TestParamInfo<TrialCase>& info) {
  const TrialCase& c = info.param;
  return std::to_string(c.inliers) + "in" + std::to_string(c.outliers) + "out_min" + std::to_string(c.min_iterations) +
         "_max" + std::to_string(c.max_iterations);
}

class RansacTrials : public ::testing::TestWithParam<TrialCase> {};

// The adaptive stopping rule: once the planted line (inlier ratio w) is the best model, RANSAC
// draws N = log(1 - p) / log(1 - w^s) samples in all (rounded up), at least min_iterations, at
// most max_iterations. The expected counts are worked out by hand in the cases below and checked
// against the formula here. (A seed whose first all-inlier pair came after N draws would stop
// later; with p >= 0.99 that happens to at most 1 % of seeds, and these are fixed.)
TEST_P(RansacTrials, IterationsFollowTheAdaptiveRule) {
  const TrialCase c = GetParam();
  const int n = c.inliers + c.outliers;
  const double w = static_cast<double>(c.inliers) / n;
  const double p_good = w * w;
  const int formula = p_good >= 1.0 ? 0 : static_cast<int>(std::ceil(std::log(1 - c.confidence) / std::log(1 - p_good)));
  ASSERT_EQ(std::max(c.min_iterations, std::min(formula, c.max_iterations)), c.expected);
  EXPECT_EQ(ransacTrials(w, 2, c.confidence), formula);

  for (int seed = 1; seed <= 3; ++seed) {
    const PlantedLine planted = plantLine(c.inliers, c.outliers, 10 * seed + c.inliers);
    RansacOptions options;
    options.max_error = 0.01;
    options.confidence = c.confidence;
    options.min_iterations = c.min_iterations;
    options.max_iterations = c.max_iterations;
    options.seed = seed;
    const auto result = ransac(planted.estimator, options);
    ASSERT_TRUE(result.success);
    EXPECT_EQ(result.num_inliers, c.inliers) << "seed " << seed;
    EXPECT_EQ(result.inliers, planted.inlier) << "seed " << seed;
    EXPECT_EQ(result.iterations, c.expected) << "seed " << seed << ", w " << w;
    EXPECT_EQ(result.capped, formula > c.max_iterations) << "seed " << seed;  // ran out before its confidence
  }
}

// The trial count at its edges: no inlier, none needed with every datum one, and a sample whose
// all-inlier probability is below double's epsilon (1 - it is 1: log1p keeps the count finite).
TEST(RansacTrialCount, EdgesOfTheInlierRatio) {
  EXPECT_EQ(ransacTrials(0.0, 8, 0.999), HUGE_VAL);
  EXPECT_EQ(ransacTrials(1.0, 8, 0.999), 0.0);
  const double tiny = ransacTrials(0.001, 8, 0.999);  // 1e-24 a sample
  EXPECT_TRUE(std::isfinite(tiny));
  EXPECT_NEAR(tiny / 6.9e24, 1.0, 0.01);  // -log(0.001) / 1e-24
  EXPECT_EQ(ransacTrials(0.5, 8, 0.999), 1765);
  EXPECT_EQ(ransacTrials(0.8, 4, 0.999), 14);
}

// A line through noisy points: a model through two of them leans and misses the inliers far
// along it; refitOnInliers' least-squares refits (the estimator fits more than two points by
// total least squares) find them all, in more than one refit, and stop when they stop growing.
struct FittingLineEstimator : LineEstimator {
  std::vector<Model> estimate(const std::vector<int>& sample) const {
    if (sample.size() == 2) return LineEstimator::estimate(sample);
    Vec2 mean = Vec2::Zero();
    for (int i : sample) mean += points[i];
    mean /= static_cast<double>(sample.size());
    Mat2 scatter = Mat2::Zero();
    for (int i : sample) scatter += (points[i] - mean) * (points[i] - mean).transpose();
    const Vec2 normal = Eigen::SelfAdjointEigenSolver<Mat2>(scatter).eigenvectors().col(0);
    return {Vec3(normal.x(), normal.y(), -normal.dot(mean))};
  }
};

TEST(RansacLocalRefits, FindTheInliersAMinimalSampleMisses) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5, 5);
  std::normal_distribution<double> noise(0, 0.004);
  FittingLineEstimator estimator;
  for (int i = 0; i < 200; ++i) {
    const double x = u(rng);
    estimator.points.emplace_back(x, 0.5 * x + 1 + noise(rng));
  }
  RansacOptions options;
  options.max_error = 0.01;
  options.min_iterations = options.max_iterations = 3;  // a few minimal samples: a leaning line
  auto result = ransac(estimator, options);
  ASSERT_TRUE(result.success);
  const int sampled = result.num_inliers;
  refitOnInliers(estimator, options, 1, &result);
  const int after_one = result.num_inliers;
  refitOnInliers(estimator, options, 10, &result);
  EXPECT_LT(sampled, after_one);
  EXPECT_LE(after_one, result.num_inliers);
  EXPECT_GE(result.num_inliers, 195);  // within 0.01 of the line: 98.8 % of 0.004 noise, 2.5 sigma
  int flagged = 0;
  for (char c : result.inliers) flagged += c;
  EXPECT_EQ(flagged, result.num_inliers);
  // The true line's normal (1, -2) / sqrt(5), up to sign.
  EXPECT_NEAR(std::abs(result.model.head<2>().dot(Vec2(1, -2) / std::sqrt(5.0))), 1.0, 1e-4);
}

INSTANTIATE_TEST_SUITE_P(
    Cases, RansacTrials,
    ::testing::Values(TrialCase{50, 50, 0.999, 1, 1000, 25},    // log(0.001) / log(0.75) = 24.01
                      TrialCase{30, 70, 0.99, 1, 1000, 49},     // log(0.01) / log(0.91) = 48.83
                      TrialCase{60, 40, 0.999, 1, 1000, 16},    // log(0.001) / log(0.64) = 15.48
                      TrialCase{80, 20, 0.999, 20, 1000, 20},   // 6.76 -> 7, raised to min_iterations
                      TrialCase{20, 80, 0.999, 1, 100, 100},    // 169.2 -> 170, cut to max_iterations
                      TrialCase{40, 0, 0.999, 5, 1000, 5}),     // w = 1: no more than min_iterations
    trialName);

// Too few data for one sample: no model, no draw.
TEST(Ransac, FewerDataThanASampleFails) {
  LineEstimator estimator;
  estimator.points = {Vec2(0, 0)};
  const auto result = ransac(estimator, RansacOptions{});
  EXPECT_FALSE(result.success);
  EXPECT_EQ(result.iterations, 0);
  EXPECT_TRUE(result.inliers.empty());
}

// The eight-point essential matrix (two_view_motion's estimator) on exact correspondences, 30 %
// of them replaced by mismatches whose Sampson distance under the true E is over 10 times the
// 1 px threshold: the inliers returned are exactly the planted ones.
struct PlantedMatches {
  std::vector<Vec2> xy_a, xy_b;
  std::vector<char> inlier;
};

constexpr double kFocalPx = 525.0;

PlantedMatches plantMatches(const SE3& T_b_a, int n, double outlier_fraction, int seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_real_distribution<double> unit(0, 1);
  const Mat3 E = essentialFromMotion(T_b_a);
  PlantedMatches m;
  while (static_cast<int>(m.xy_a.size()) < n) {
    const Vec3 p_a(1.5 * u(rng), 1.0 * u(rng), 3.0 + 1.5 * u(rng));
    const Vec3 p_b = T_b_a * p_a;
    if (p_b.z() < 0.5) continue;
    Vec2 xy_b = p_b.hnormalized();
    const bool outlier = unit(rng) < outlier_fraction;
    if (outlier) {
      xy_b = Vec2(0.6 * u(rng), 0.45 * u(rng));
      if (kFocalPx * kFocalPx * sampsonErrorSquared(E, p_a.hnormalized(), xy_b) < 100.0) continue;
    }
    m.xy_a.push_back(p_a.hnormalized());
    m.xy_b.push_back(xy_b);
    m.inlier.push_back(!outlier);
  }
  return m;
}

class RansacEssential : public ::testing::TestWithParam<int> {};

TEST_P(RansacEssential, InliersAreExactlyThePlantedOnes) {
  const int k = GetParam();
  const SE3 T_b_a = SE3::fromRotvec(Vec3(0.05 * std::sin(k), 0.1 * std::cos(k), 0.03 * k),
                                    Vec3(0.2 * std::cos(k), 0.05, 0.1 * std::sin(k)));
  const PlantedMatches m = plantMatches(T_b_a, 120, 0.3, 40 + k);
  RansacOptions options;
  options.max_error = 1.0;  // pixels; exact inliers are at ~1e-10 px, outliers over 10 px
  const EssentialEstimator estimator{m.xy_a, m.xy_b, kFocalPx * kFocalPx};
  const auto result = ransac(estimator, options);
  ASSERT_TRUE(result.success);
  EXPECT_EQ(result.inliers, m.inlier);
  int planted = 0;
  for (char c : m.inlier) planted += c;
  EXPECT_EQ(result.num_inliers, planted);
  EXPECT_LT(result.iterations, options.max_iterations);  // w ~ 0.7: N = log(0.001) / log(1 - w^8) ~ 120

  // The same through estimateTwoViewMotion (RANSAC, refinement, cheirality).
  const TwoViewResult motion = estimateTwoViewMotion(m.xy_a, m.xy_b, kFocalPx, TwoViewOptions{});
  ASSERT_TRUE(motion.ok) << motion.reason;
  EXPECT_EQ(motion.inliers, m.inlier);
  EXPECT_LT(rotationAngle(motion.T_b_a.R().transpose() * T_b_a.R()), 1e-6);
  EXPECT_LT((motion.T_b_a.t() - T_b_a.t().normalized()).norm(), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Motions, RansacEssential, ::testing::Range(1, 6));

// The refinement's Cauchy cost, taken as the logarithm of a product, is the sum of the losses: where
// 30 % of the tracks are outliers over 10 px (the losses' sum passes log(DBL_MAX), 709.8, so a
// plain product would overflow), and where exact tracks leave losses of 1e-25 each.
TEST(RefineTwoViewMotion, ReportsTheSumOfTheCauchyLosses) {
  const SE3 T_b_a = SE3::fromRotvec(Vec3(0.02, -0.05, 0.01), Vec3(0.2, 0.05, 0.03));
  const double c = 1.0 / kFocalPx;  // 1 pixel
  const SE3 start(rotationFromRotvec(Vec3(0.01, 0, 0)) * T_b_a.R(), T_b_a.t().normalized());
  for (const double outlier_fraction : {0.3, 0.0}) {
    SCOPED_TRACE(outlier_fraction);
    const PlantedMatches m = plantMatches(T_b_a, 200, outlier_fraction, 7);
    auto sumOfLosses = [&](const SE3& T) {
      const Mat3 E = essentialFromMotion(T);
      double sum = 0;
      for (size_t i = 0; i < m.xy_a.size(); ++i)
        sum += c * c * std::log1p(sampsonErrorSquared(E, m.xy_a[i], m.xy_b[i]) / (c * c));
      return sum;
    };
    double start_cost = 0, cost = 0;
    refineTwoViewMotion(start, m.xy_a, m.xy_b, 0, c, &start_cost);
    const double expected_start = sumOfLosses(start);
    EXPECT_NEAR(start_cost, expected_start, 1e-12 * expected_start);
    const SE3 refined = refineTwoViewMotion(start, m.xy_a, m.xy_b, 10, c, &cost);
    const double expected = sumOfLosses(refined);
    EXPECT_NEAR(cost, expected, 1e-12 * expected);
    EXPECT_LT(cost, start_cost);
    const double angle = rotationAngle(refined.R().transpose() * T_b_a.R());
    EXPECT_LT(angle, 1e-3);  // 0.57 degrees off at the start
    if (outlier_fraction == 0) {
      EXPECT_LT(angle, 1e-9);
      EXPECT_LT(expected, 200 * 1e-20 * c * c);
    }
  }
}

}  // namespace
}  // namespace slamcmp
