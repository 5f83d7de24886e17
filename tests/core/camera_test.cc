// The camera model against OpenCV's projectPoints/undistortPoints and its Jacobians against
// numeric differences, for the 4, 5 and 8 coefficient distortion models.
#include "core/camera.h"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <random>
#include <string>
#include <vector>

#include "tests/test_util.h"

namespace slamcmp {
namespace {

struct CameraCase {
  std::string name;
  CameraModel camera;
};

// gtest prints the parameter by its name.
void PrintTo(const CameraCase& c, std::ostream* os) { *os << c.name; }

CameraModel makeCamera(int n, std::array<double, 8> d) {
  CameraModel c;
  c.width = 640;
  c.height = 480;
  c.fx = 517.3;
  c.fy = 516.5;
  c.cx = 318.6;
  c.cy = 255.3;
  c.num_distortion = n;
  c.distortion = d;
  return c;
}

std::vector<CameraCase> cameraCases() {
  return {
      // Barrel distortion of a wide lens (vamr-like) with tangential terms.
      {"four", makeCamera(4, {-0.2966, 0.0808, 1.2e-3, -8e-4, 0, 0, 0, 0})},
      // TUM freiburg1 RGB: strong k3.
      {"five", makeCamera(5, {0.262383, -0.953104, -0.005358, 0.002628, 1.163314, 0, 0, 0})},
      // Rational model with all terms.
      {"eight", makeCamera(8, {0.45, -0.12, 9e-4, -6e-4, 0.03, 0.62, -0.08, 0.015})},
  };
}

// Random points in front of the camera whose images fall inside the frame (with some margin).
std::vector<Vec3> pointsInView(const CameraModel& c, int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, c.width - 1.0), v(0.0, c.height - 1.0), z(0.3, 8.0);
  CameraModel pinhole = c;
  pinhole.distortion.fill(0.0);
  std::vector<Vec3> out;
  while (static_cast<int>(out.size()) < n) {
    const Vec2 xy = pinhole.normalisedFromPixel(Vec2(u(rng), v(rng)));
    const double depth = z(rng);
    out.emplace_back(xy.x() * depth, xy.y() * depth, depth);
  }
  return out;
}

class CameraModelTest : public ::testing::TestWithParam<CameraCase> {};

TEST_P(CameraModelTest, ProjectMatchesCvProjectPoints) {
  const CameraModel& c = GetParam().camera;
  const std::vector<Vec3> points = pointsInView(c, 500, 1);
  std::vector<cv::Point3d> cv_points;
  for (const Vec3& p : points) cv_points.emplace_back(p.x(), p.y(), p.z());
  std::vector<cv::Point2d> uv_cv;
  cv::projectPoints(cv_points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), c.cameraMatrix(),
                    c.distortionVector(), uv_cv);
  for (size_t k = 0; k < points.size(); ++k) {
    const Vec2 uv = c.project(points[k]);
    EXPECT_NEAR(uv.x(), uv_cv[k].x, 1e-9) << "point " << k;
    EXPECT_NEAR(uv.y(), uv_cv[k].y, 1e-9) << "point " << k;
  }
}

TEST_P(CameraModelTest, DistortMatchesCvProjectPointsWithIdentityK) {
  const CameraModel& c = GetParam().camera;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  std::vector<cv::Point3d> rays;
  std::vector<Vec2> xys;
  for (int k = 0; k < 300; ++k) {
    xys.emplace_back(u(rng), 0.75 * u(rng));
    rays.emplace_back(xys.back().x(), xys.back().y(), 1.0);
  }
  std::vector<cv::Point2d> xy_cv;
  cv::projectPoints(rays, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), cv::Matx33d::eye(),
                    c.distortionVector(), xy_cv);
  for (size_t k = 0; k < xys.size(); ++k) {
    const Vec2 xy_distorted = c.distort(xys[k]);
    EXPECT_NEAR(xy_distorted.x(), xy_cv[k].x, 1e-12);
    EXPECT_NEAR(xy_distorted.y(), xy_cv[k].y, 1e-12);
  }
}

TEST_P(CameraModelTest, UndistortMatchesCvUndistortPoints) {
  const CameraModel& c = GetParam().camera;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(20.0, c.width - 21.0), v(20.0, c.height - 21.0);
  std::vector<cv::Point2d> uv_distorted;
  for (int k = 0; k < 300; ++k) uv_distorted.emplace_back(u(rng), v(rng));
  std::vector<cv::Point2d> xy_cv;
  // OpenCV iterates a fixed point; ask for many iterations so it converges fully.
  cv::undistortPoints(
      uv_distorted, xy_cv, c.cameraMatrix(), c.distortionVector(), cv::noArray(), cv::noArray(),
      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 1000, 1e-15));
  int compared = 0;
  for (size_t k = 0; k < uv_distorted.size(); ++k) {
    const Vec2 xy = c.undistortPixel(Vec2(uv_distorted[k].x, uv_distorted[k].y));
    // Both must reproduce the distorted pixel; where OpenCV's fixed point did not converge it is
    // not a reference.
    const Vec2 xy_ref(xy_cv[k].x, xy_cv[k].y);
    if ((c.pixelFromNormalised(c.distort(xy_ref)) - Vec2(uv_distorted[k].x, uv_distorted[k].y))
            .norm() > 1e-6)
      continue;
    ++compared;
    EXPECT_NEAR(xy.x(), xy_ref.x(), 1e-9 / c.fx) << "pixel " << k;
    EXPECT_NEAR(xy.y(), xy_ref.y(), 1e-9 / c.fy) << "pixel " << k;
  }
  EXPECT_GE(compared, 250) << "OpenCV's undistortPoints converged too rarely to compare";
}

TEST_P(CameraModelTest, UndistortInvertsDistort) {
  const CameraModel& c = GetParam().camera;
  for (const Vec3& p : pointsInView(c, 500, 4)) {
    const Vec2 xy(p.x() / p.z(), p.y() / p.z());
    const Vec2 uv_distorted = c.project(p);
    EXPECT_LT((c.undistort(c.distort(xy)) - xy).norm(), 1e-12);
    EXPECT_LT((c.undistortPixel(uv_distorted) - xy).norm(), 1e-12);
    // Undistorted pixel: the ideal pinhole image of the same point.
    const Vec2 uv_undistorted = c.pixelFromNormalised(xy);
    EXPECT_LT((c.undistortToPixel(uv_distorted) - uv_undistorted).norm(), 1e-9);
    EXPECT_LT((c.normalisedFromPixel(uv_undistorted) - xy).norm(), 1e-15);
  }
}

TEST_P(CameraModelTest, DistortJacobianMatchesNumeric) {
  const CameraModel& c = GetParam().camera;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-0.6, 0.6);
  for (int k = 0; k < 30; ++k) {
    const Eigen::VectorXd xy = Vec2(u(rng), 0.75 * u(rng));
    Mat2 J;
    c.distort(xy, &J);
    test::expectJacobianMatchesNumeric(
        [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return c.distort(Vec2(x)); }, xy, J,
        1e-7);
  }
}

TEST_P(CameraModelTest, ProjectJacobianMatchesNumeric) {
  const CameraModel& c = GetParam().camera;
  for (const Vec3& p : pointsInView(c, 30, 6)) {
    Eigen::Matrix<double, 2, 3> J;
    c.project(p, &J);
    test::expectJacobianMatchesNumeric(
        [&](const Eigen::VectorXd& x) -> Eigen::VectorXd { return c.project(Vec3(x)); },
        Eigen::VectorXd(p), J, 1e-6);
  }
}

TEST_P(CameraModelTest, OpenCVMatricesRoundTrip) {
  const CameraModel& c = GetParam().camera;
  EXPECT_EQ(c.distortionVector().total(), static_cast<size_t>(c.num_distortion));
  const CameraModel back =
      CameraModel::fromOpenCV(c.cameraMatrix(), c.distortionVector(), cv::Size(c.width, c.height));
  EXPECT_EQ(back.num_distortion, c.num_distortion);
  EXPECT_EQ(back.distortion, c.distortion);
  EXPECT_EQ(back.K(), c.K());
  EXPECT_TRUE(back.hasDistortion());
}

INSTANTIATE_TEST_SUITE_P(DistortionModels, CameraModelTest, ::testing::ValuesIn(cameraCases()),
                         [](const auto& info) { return info.param.name; });

TEST(CameraModel, WithoutDistortionUndistortIsTheIdentity) {
  CameraModel c = makeCamera(5, {});
  EXPECT_FALSE(c.hasDistortion());
  const Vec2 xy(0.31, -0.27);
  EXPECT_EQ(c.distort(xy), xy);
  EXPECT_EQ(c.undistort(xy), xy);
  // The pixel grid: (0,0) is the top-left pixel's centre, the image spans [-0.5, w-0.5).
  EXPECT_TRUE(c.inImage(Vec2(-0.5, -0.5)));
  EXPECT_FALSE(c.inImage(Vec2(c.width - 0.5, 10)));
  EXPECT_FALSE(c.inImage(Vec2(2, 2), 3.0));
}

}  // namespace
}  // namespace slamcmp
