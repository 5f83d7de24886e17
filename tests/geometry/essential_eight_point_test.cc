#include "geometry/essential_eight_point.h"

#include <random>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "geometry/two_view_motion.h"

namespace slamcmp {
namespace {

// Points in a room-like volume in front of camera a, and their normalised coordinates in a and b.
struct Scene {
  std::vector<Vec2> xy_a, xy_b;
};

Scene makeScene(const SE3& T_b_a, int n, double noise_normalised, int seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> noise(0, noise_normalised);
  Scene s;
  while (static_cast<int>(s.xy_a.size()) < n) {
    const Vec3 p_a(u(rng) * 1.5, u(rng) * 1.0, 2.5 + 1.5 * u(rng));
    const Vec3 p_b = T_b_a * p_a;
    if (p_b.z() < 0.5) continue;
    s.xy_a.push_back(p_a.hnormalized() + Vec2(noise(rng), noise(rng)));
    s.xy_b.push_back(p_b.hnormalized() + Vec2(noise(rng), noise(rng)));
  }
  return s;
}

SE3 motion(int k) {
  return SE3::fromRotvec(Vec3(0.05 * std::sin(k), 0.1 * std::cos(k), 0.03 * k), Vec3(0.2 * std::cos(k), 0.05, 0.1 * std::sin(k)));
}

double angleDeg(const Mat3& A, const Mat3& B) { return rotationAngle(A.transpose() * B) * 180 / M_PI; }

class EssentialExact : public ::testing::TestWithParam<int> {};

TEST_P(EssentialExact, RecoversRotationExactlyAndTranslationUpToScale) {
  const SE3 truth = motion(GetParam());
  const Scene s = makeScene(truth, 40, 0, GetParam());
  const Mat3 E = essentialEightPoint(s.xy_a, s.xy_b);
  Eigen::JacobiSVD<Mat3> svd(E);
  EXPECT_NEAR(svd.singularValues()(0), 1.0, 1e-12);
  EXPECT_NEAR(svd.singularValues()(1), 1.0, 1e-12);
  EXPECT_NEAR(svd.singularValues()(2), 0.0, 1e-12);
  for (size_t i = 0; i < s.xy_a.size(); ++i) EXPECT_LT(sampsonErrorSquared(E, s.xy_a[i], s.xy_b[i]), 1e-20);
  int in_front = 0;
  const SE3 pose = selectByCheirality(E, s.xy_a, s.xy_b, &in_front);
  EXPECT_EQ(in_front, 40);
  EXPECT_LT(angleDeg(pose.R(), truth.R()), 1e-9);
  EXPECT_LT((pose.t() - truth.t().normalized()).norm(), 1e-9);
  // Exactly one of the four candidates has every point in front.
  int all_in_front = 0;
  for (const SE3& c : decomposeEssential(E)) all_in_front += countInFront(c, s.xy_a, s.xy_b) == 40;
  EXPECT_EQ(all_in_front, 1);
}

INSTANTIATE_TEST_SUITE_P(Motions, EssentialExact, ::testing::Range(0, 6));

// 0.5 px noise (f = 500) and 33 % gross outliers: RANSAC finds the outliers; the motion is within
// 0.2 degree (rotation) and 2 degrees (translation direction) of the truth.
TEST(TwoViewMotion, RobustToOutliersAndAgreesWithOpenCV) {
  const double f = 500;
  for (int k = 0; k < 4; ++k) {
    const SE3 truth = motion(k);
    Scene s = makeScene(truth, 150, 0.5 / f, 10 + k);
    std::mt19937 rng(k);
    std::uniform_real_distribution<double> u(-0.5, 0.5);
    std::vector<char> outlier(s.xy_a.size(), 0);
    for (size_t i = 0; i < s.xy_a.size(); i += 3) s.xy_b[i] += Vec2(u(rng), u(rng)) * 0.2, outlier[i] = 1;
    TwoViewOptions options;
    options.ransac.max_error = 2.0;  // about 3 sigma of the Sampson distance of 0.5 px noise in both views
    const TwoViewResult r = estimateTwoViewMotion(s.xy_a, s.xy_b, f, options);
    ASSERT_TRUE(r.ok) << r.reason;
    int outliers_kept = 0, inliers_lost = 0;
    for (size_t i = 0; i < outlier.size(); ++i) {
      const double sampson_px = std::sqrt(sampsonErrorSquared(essentialFromMotion(truth), s.xy_a[i], s.xy_b[i])) * f;
      outliers_kept += outlier[i] && r.inliers[i] && sampson_px > 3.0;
      inliers_lost += !outlier[i] && !r.inliers[i];
    }
    EXPECT_EQ(outliers_kept, 0);
    EXPECT_LE(inliers_lost, 10);  // of 100, threshold about 3 sigma
    EXPECT_LT(angleDeg(r.T_b_a.R(), truth.R()), 0.2);
    EXPECT_LT(std::acos(std::clamp(r.T_b_a.t().dot(truth.t().normalized()), -1.0, 1.0)) * 180 / M_PI, 2.0);

    std::vector<cv::Point2d> a, b;
    for (size_t i = 0; i < s.xy_a.size(); ++i)
      a.emplace_back(s.xy_a[i].x(), s.xy_a[i].y()), b.emplace_back(s.xy_b[i].x(), s.xy_b[i].y());
    cv::Mat mask;
    const cv::Mat E = cv::findEssentialMat(a, b, cv::Mat::eye(3, 3, CV_64F), cv::RANSAC, 0.999, 1.0 / f, mask);
    cv::Mat R, t;
    cv::recoverPose(E, a, b, cv::Mat::eye(3, 3, CV_64F), R, t, mask);
    Mat3 R_cv;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) R_cv(i, j) = R.at<double>(i, j);
    const Vec3 t_cv(t.at<double>(0), t.at<double>(1), t.at<double>(2));
    // At least as close to the truth as OpenCV's 5-point RANSAC with recoverPose (which has no
    // refinement on the inliers), within 0.02 degree and 0.2 degree.
    const double t_err = std::acos(std::clamp(r.T_b_a.t().dot(truth.t().normalized()), -1.0, 1.0)) * 180 / M_PI;
    const double t_err_cv = std::acos(std::clamp(t_cv.dot(truth.t().normalized()), -1.0, 1.0)) * 180 / M_PI;
    EXPECT_LT(angleDeg(r.T_b_a.R(), truth.R()), angleDeg(R_cv, truth.R()) + 0.02);
    EXPECT_LT(t_err, t_err_cv + 0.2);
  }
}

TEST(TwoViewMotion, PureRotationIsReportedDegenerate) {
  const SE3 rotation_only = SE3::fromRotvec(Vec3(0.02, 0.05, 0.01), Vec3::Zero());
  const Scene s = makeScene(rotation_only, 100, 0.2 / 500, 5);
  const TwoViewResult r = estimateTwoViewMotion(s.xy_a, s.xy_b, 500, {});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("degenerate"), std::string::npos) << r.reason;
  EXPECT_TRUE(r.degenerate);
  EXPECT_LT(r.parallax_px, 1.0);
  EXPECT_LT(rotationAngle(r.T_b_a.R().transpose() * rotation_only.R()) * 180 / M_PI, 0.1);  // the rotation stands
}

TEST(TwoViewMotion, TooFewCorrespondencesIsNotAMotion) {
  const Scene s = makeScene(motion(1), 10, 0, 1);
  const TwoViewResult r = estimateTwoViewMotion(s.xy_a, s.xy_b, 500, {});
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.reason.empty());
}

}  // namespace
}  // namespace slamcmp
