#include "ekf/patch_warp.h"

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "tests/ekf/plane_render.h"

namespace slamcmp {
namespace {

// Camera 0 looks at the textured plane z = 0 from 1 m; camera 1 has moved sideways, closer, and
// rolled: the warped template must look like what camera 1 sees, much more than the unwarped one.
TEST(PatchWarp, WarpedTemplateMatchesTheNewView) {
  const CameraModel camera = test::testCamera();
  const SE3 T0 = SE3::fromRotvec(Vec3(0, 0, 0), Vec3(0, 0, -1.0));
  const SE3 T1 = SE3::fromRotvec(Vec3(0.15, -0.25, 1.2), Vec3(0.25, 0.1, -0.7));
  const cv::Mat image0 = test::renderPlane(camera, T0, 0.0);
  const cv::Mat image1 = test::renderPlane(camera, T1, 0.0);
  const Vec3 y(0.05, 0.03, 0.0);
  const Vec2 uv0 = camera.project(T0.inverse() * y);
  const Vec2 uv1 = camera.project(T1.inverse() * y);
  PatchSource source, source1;
  ASSERT_TRUE(makePatchSource(image0, uv0, 41, T0, &source));
  ASSERT_TRUE(makePatchSource(image1, uv1, 41, T1, &source1));
  cv::Mat warped, unwarped, seen;
  ASSERT_TRUE(warpTemplate(source, camera, T1, y, uv1, 11, &warped));
  ASSERT_TRUE(sourceTemplate(source, 11, &unwarped));
  ASSERT_TRUE(sourceTemplate(source1, 11, &seen));
  // The correlation active search scores a template with (patch_search.cc).
  auto ncc = [&](const cv::Mat& templ) {
    cv::Mat score;
    cv::matchTemplate(seen, templ, score, cv::TM_CCOEFF_NORMED);
    return static_cast<double>(score.at<float>(0, 0));
  };
  const double ncc_warped = ncc(warped);
  EXPECT_GT(ncc_warped, 0.98);
  EXPECT_LT(ncc(unwarped), ncc_warped - 0.2);
}

TEST(PatchWarp, SameViewReproducesTheSourcePatch) {
  const CameraModel camera = test::testCamera();
  const SE3 T0 = SE3::fromRotvec(Vec3(0.1, 0, 0), Vec3(0, 0, -1.0));
  const cv::Mat image0 = test::renderPlane(camera, T0, 0.0);
  const Vec3 y(0.02, -0.04, 0.0);
  const Vec2 uv0 = camera.project(T0.inverse() * y);
  PatchSource source;
  ASSERT_TRUE(makePatchSource(image0, uv0, 41, T0, &source));
  cv::Mat warped, original;
  ASSERT_TRUE(warpTemplate(source, camera, T0, y, uv0, 11, &warped));
  ASSERT_TRUE(sourceTemplate(source, 11, &original));
  EXPECT_LT(cv::norm(warped, original, cv::NORM_INF), 0.5);
}

TEST(PatchWarp, SourceCropMustFitInTheImage) {
  PatchSource source;
  EXPECT_FALSE(makePatchSource(cv::Mat(480, 640, CV_8U, cv::Scalar(0)), Vec2(10, 10), 41, SE3(), &source));
}

}  // namespace
}  // namespace slamcmp
