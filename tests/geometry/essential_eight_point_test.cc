#include "geometry/essential_eight_point.h"

#include <cmath>
#include <limits>
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

// Points on one plane (a wall 2 m away, tilted) fit a family of essential matrices (Hartley and
// Zisserman 11.9): RANSAC's is one of them, and its motion was returned as ok, a few degrees and
// tens of degrees of translation off (a review: 3 of 6 motions). A homography explains the inliers:
// no motion. Off (max_homography_inlier_ratio 1) the same views give the wrong motion.
TEST(TwoViewMotion, APlanarSceneIsNotAMotion) {
  int wrong_without_the_test = 0;
  for (int k = 1; k <= 6; ++k) {
    SCOPED_TRACE(k);
    const SE3 truth = motion(k);
    std::mt19937 rng(k);
    std::uniform_real_distribution<double> u(-1, 1);
    std::normal_distribution<double> noise(0, 0.5 / 500);
    std::vector<Vec2> a, b;
    while (a.size() < 150) {
      const double x = 1.5 * u(rng), y = u(rng);
      const Vec3 p_a(x, y, 2.0 + 0.3 * x);
      const Vec3 p_b = truth * p_a;
      if (p_b.z() < 0.5) continue;
      a.push_back(p_a.hnormalized() + Vec2(noise(rng), noise(rng)));
      b.push_back(p_b.hnormalized() + Vec2(noise(rng), noise(rng)));
    }
    const TwoViewResult r = estimateTwoViewMotion(a, b, 500, {});
    EXPECT_FALSE(r.ok);
    EXPECT_TRUE(r.planar);
    EXPECT_NE(r.reason.find("planar"), std::string::npos) << r.reason;
    TwoViewOptions untested;
    untested.max_homography_inlier_ratio = 1;
    const TwoViewResult u_r = estimateTwoViewMotion(a, b, 500, untested);
    EXPECT_FALSE(u_r.planar);
    wrong_without_the_test += u_r.ok && angleDeg(u_r.T_b_a.R(), truth.R()) > 1.0;
  }
  EXPECT_GE(wrong_without_the_test, 2);  // what the test is for
}

// A scene in depth beside the plane's: points on a wall with a third of them in front of it still
// give the motion (the homography explains too few).
TEST(TwoViewMotion, AWallWithThingsInFrontOfItIsAMotion) {
  const SE3 truth = motion(2);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vec2> a, b;
  for (int i = 0; a.size() < 150; ++i) {
    const double x = 1.5 * u(rng), y = u(rng);
    const Vec3 p_a(x, y, i % 3 == 0 ? 1.0 + 0.5 * u(rng) : 2.0 + 0.3 * x);
    const Vec3 p_b = truth * p_a;
    if (p_b.z() < 0.5) continue;
    a.push_back(p_a.hnormalized());
    b.push_back(p_b.hnormalized());
  }
  const TwoViewResult r = estimateTwoViewMotion(a, b, 500, {});
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_LT(angleDeg(r.T_b_a.R(), truth.R()), 0.01);
}

// A scene 2-4 m deep seen 3 cm apart (median parallax about 5 px, 0.3 px noise) is not taken for
// a plane: a homography with the views' noise in both images (1.77 times the Sampson threshold)
// took 47 of 50 such pairs for one (a review).
TEST(TwoViewMotion, ADeepSceneWithAFewPixelsOfParallaxIsNotPlanar) {
  int planar = 0;
  for (int seed = 0; seed < 20; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    std::normal_distribution<double> noise(0, 0.3 / 500);
    const SE3 truth = SE3::fromRotvec(Vec3(0.01 * u(rng), 0.03 * u(rng), 0.01 * u(rng)),
                                      Vec3(0.03, 0.006 * u(rng), 0.006 * u(rng)));
    std::vector<Vec2> a, b;
    while (a.size() < 150) {
      const double z = 2.0 + (1 + u(rng));
      const Vec3 p(0.6 * z * u(rng), 0.45 * z * u(rng), z);
      a.push_back(p.hnormalized() + Vec2(noise(rng), noise(rng)));
      b.push_back((truth * p).hnormalized() + Vec2(noise(rng), noise(rng)));
    }
    planar += estimateTwoViewMotion(a, b, 500, {}).planar;
  }
  EXPECT_EQ(planar, 0);
}

// Half the correspondences wrong (the smallest inlier ratio accepted, 0.5, plus a margin): an
// all-inlier sample of 8 at 0.55 takes 822 draws for 0.999, and 300 (the cap before) found the
// motion in 22 of 100 such draws (a review). Over 20 RANSAC seeds the new cap and the local refits
// find it in most; the rest fail saying RANSAC ran out of samples (a minimal sample through noisy
// points is itself off: a 5-point solver would do better), never with a wrong motion.
TEST(TwoViewMotion, HalfTheMatchesWrongStillGivesTheMotion) {
  const SE3 truth = SE3::fromRotvec(Vec3(0.02, 0.1, 0.03), Vec3(0.2, 0.05, 0.1));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> noise(0, 0.3 / 500);
  std::vector<Vec2> a, b;
  for (int i = 0; a.size() < 200; ++i) {
    const Vec3 p_a(1.5 * u(rng), u(rng), 2.5 + 1.5 * u(rng));
    const Vec3 p_b = truth * p_a;
    if (p_b.z() < 0.5) continue;
    a.push_back(p_a.hnormalized() + Vec2(noise(rng), noise(rng)));
    b.push_back(i % 20 < 11 ? Vec2(p_b.hnormalized() + Vec2(noise(rng), noise(rng)))
                            : Vec2(0.6 * u(rng), 0.45 * u(rng)));  // 55 % inliers
  }
  int found = 0, found_capped_at_300 = 0;
  for (int seed = 1; seed <= 20; ++seed) {
    TwoViewOptions options;
    options.ransac.seed = seed;
    const TwoViewResult r = estimateTwoViewMotion(a, b, 500, options);
    found += r.ok && angleDeg(r.T_b_a.R(), truth.R()) < 0.5;
    options.ransac.max_iterations = 300;
    const TwoViewResult capped = estimateTwoViewMotion(a, b, 500, options);
    found_capped_at_300 += capped.ok && angleDeg(capped.T_b_a.R(), truth.R()) < 0.5;
    for (const TwoViewResult* result : {&r, &capped}) {
      if (!result->ok) {
        EXPECT_NE(result->reason.find("RANSAC stopped at its"), std::string::npos) << result->reason;
      } else {
        EXPECT_LT(angleDeg(result->T_b_a.R(), truth.R()), 0.5);
      }
    }
  }
  // Measured: 14 of 20, and 6 with the old cap (10 with the new cap before the local refits).
  EXPECT_GE(found, 13);
  EXPECT_LE(found_capped_at_300, 8);
}

// A correspondence whose Sampson distance is not defined (a coordinate NaN: 0 / 0) fits no
// model: it counted as a perfect fit of every one, a NaN model's too, and one such track among
// 150 good ones gave "too few two-view inliers (1 of 150)".
TEST(TwoViewMotion, ANonFiniteCorrespondenceFitsNoModel) {
  Scene s = makeScene(motion(3), 150, 0.3 / 500, 3);
  s.xy_b[17] = Vec2(std::nan(""), 0.1);
  EXPECT_EQ(sampsonErrorSquared(essentialFromMotion(motion(3)), s.xy_a[17], s.xy_b[17]),
            std::numeric_limits<double>::infinity());
  const TwoViewResult r = estimateTwoViewMotion(s.xy_a, s.xy_b, 500, {});
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_FALSE(r.inliers[17]);
  EXPECT_LT(angleDeg(r.T_b_a.R(), motion(3).R()), 0.1);
}

}  // namespace
}  // namespace slamcmp
